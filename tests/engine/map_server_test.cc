// map_server import/export: YAML values and pixels survive unchanged; occupancy follows map_server's rules.
#include "engine/grid/map_server.h"

#include <gtest/gtest.h>

#include <optional>


#include "schema/error.h"
#include "sim/png_writer.h"

namespace anchordb::engine {
namespace map_server_test {

GreyImage Gradient(int w, int h) {
  GreyImage img{w, h, {}};
  for (int i = 0; i < w * h; ++i) img.pixels.push_back(static_cast<std::uint8_t>((i * 37) % 256));
  return img;
}

TEST(MapServerYamlTest, ParsesEveryKeyAndReportsUnknownOnes) {
  const auto parsed = ParseMapServerYaml(
      "image: house.pgm\nresolution: 0.025\norigin: [-3.25, 7.5, 0.1]\nnegate: 1\n"
      "occupied_thresh: 0.7\nfree_thresh: 0.2\nmode: scale\nextra: 3\n");
  EXPECT_EQ(parsed.meta.image, "house.pgm");
  EXPECT_DOUBLE_EQ(parsed.meta.resolution_m, 0.025);
  EXPECT_DOUBLE_EQ(parsed.meta.origin[0], -3.25);
  EXPECT_DOUBLE_EQ(parsed.meta.origin[2], 0.1);
  EXPECT_EQ(parsed.meta.negate, 1);
  EXPECT_EQ(parsed.meta.mode, MapMode::kScale);
  ASSERT_EQ(parsed.ignored_keys.size(), 1u);
  EXPECT_EQ(parsed.ignored_keys[0], "extra");
}

TEST(MapServerYamlTest, EmitParsesBackToTheSameValues) {
  MapServerMeta m;
  m.image = "x.pgm";
  m.resolution_m = 0.1 + 0.2;  // a value without a short exact decimal form
  m.origin[0] = -12.5;
  m.origin[1] = 1.0 / 3.0;
  m.origin[2] = 0.0;
  m.occupied_thresh = 0.65;
  m.free_thresh = 0.196;
  const auto back = ParseMapServerYaml(EmitMapServerYaml(m)).meta;
  EXPECT_EQ(back.resolution_m, m.resolution_m);
  EXPECT_EQ(back.origin[1], m.origin[1]);
  EXPECT_EQ(back.origin[0], m.origin[0]);
  EXPECT_EQ(back.occupied_thresh, m.occupied_thresh);
  EXPECT_EQ(back.free_thresh, m.free_thresh);
  EXPECT_EQ(back.negate, m.negate);
  EXPECT_FALSE(back.mode_given);
}

TEST(MapServerYamlTest, RejectsBadYaml) {
  EXPECT_THROW(ParseMapServerYaml("resolution: [oops"), Error);
  EXPECT_THROW(ParseMapServerYaml("image: a.pgm\norigin: [0,0,0]\noccupied_thresh: 0.6\nfree_thresh: 0.2\n"), Error);
  EXPECT_THROW(ParseMapServerYaml("resolution: -1\norigin: [0,0,0]\noccupied_thresh: 0.6\nfree_thresh: 0.2\n"), Error);
  EXPECT_THROW(ParseMapServerYaml("resolution: 0.1\norigin: [0,0]\noccupied_thresh: 0.6\nfree_thresh: 0.2\n"), Error);
  EXPECT_THROW(ParseMapServerYaml("resolution: 0.1\norigin: [0,0,0]\noccupied_thresh: 0.2\nfree_thresh: 0.6\n"), Error);
  EXPECT_THROW(ParseMapServerYaml("resolution: 0.1\norigin: [0,0,0]\noccupied_thresh: 0.6\nfree_thresh: 0.2\nmode: fancy\n"), Error);
}

TEST(MapServerImageTest, PgmRoundTripKeepsEveryPixel) {
  const GreyImage img = Gradient(13, 7);
  const GreyImage back = DecodeMapImage(EncodePgm(img), 1000);
  EXPECT_EQ(back.width, 13);
  EXPECT_EQ(back.height, 7);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(MapServerImageTest, PgmWithCommentsAndAsciiVariant) {
  const std::string p5 = std::string("P5\n# made by hand\n3 2\n# another\n255\n") + std::string("\x00\x10\xfe\xcd\x01\xff", 6);
  const GreyImage a = DecodeMapImage(p5, 100);
  EXPECT_EQ(a.pixels, (std::vector<std::uint8_t>{0, 16, 254, 205, 1, 255}));
  const GreyImage b = DecodeMapImage("P2\n3 2\n255\n0 16 254\n205 1 255\n", 100);
  EXPECT_EQ(b.pixels, a.pixels);
}

TEST(MapServerImageTest, PngRoundTripAndColourAveraging) {
  const GreyImage img = Gradient(9, 4);
  EXPECT_EQ(DecodeMapImage(EncodePng(img), 1000).pixels, img.pixels);
  // RGB and RGBA written by another encoder (sim/png_writer.h): colour averaged, alpha left out.
  const std::string rgb = sim::WritePng({30, 60, 90, 255, 255, 255}, 2, 1, 3, 8);
  EXPECT_EQ(DecodeMapImage(rgb, 100).pixels, (std::vector<std::uint8_t>{60, 255}));
  const std::string rgba = sim::WritePng({30, 60, 90, 0, 255, 255, 255, 7}, 2, 1, 4, 8);
  EXPECT_EQ(DecodeMapImage(rgba, 100).pixels, (std::vector<std::uint8_t>{60, 255}));
}

TEST(MapServerImageTest, RejectsGarbageTruncationAndOversize) {
  EXPECT_THROW(DecodeMapImage("hello", 100), Error);
  EXPECT_THROW(DecodeMapImage("P5\n4 4\n255\n\x01\x02", 100), Error);
  EXPECT_THROW(DecodeMapImage("P5\n4 4\n65535\n", 100), Error);
  EXPECT_THROW(DecodeMapImage(EncodePgm(Gradient(20, 20)), 100), Error);
  EXPECT_THROW(DecodeMapImage(EncodePng(Gradient(20, 20)), 100), Error);
  // An oversized PNG is refused as too large from its header alone, also when a dimension is past the PNG spec's
  // 2^31 - 1 (the header is forged; the rest of the file is not read).
  const auto code_of = [](const std::string& bytes) -> std::optional<ErrorCode> {
    try {
      DecodeMapImage(bytes, 100);
    } catch (const Error& e) {
      return e.code();
    }
    return std::nullopt;
  };
  EXPECT_EQ(code_of(EncodePng(Gradient(20, 20))), ErrorCode::kPayloadTooLarge);
  std::string forged = EncodePng(Gradient(4, 4));
  forged[16] = '\x80';  // width 2^31 + 4
  EXPECT_EQ(code_of(forged), ErrorCode::kPayloadTooLarge);
  EXPECT_EQ(code_of(EncodePng(Gradient(5, 5))), std::nullopt);  // 25 pixels: decoded, nothing thrown
}

TEST(MapServerOccupancyTest, TrinaryScaleRawAndNegate) {
  // Pixels (top row first): 0 black, 254 white, 205 grey, 100 dark grey.
  const GreyImage img{4, 1, {0, 254, 205, 100}};
  MapServerMeta m;  // trinary, 0.65 / 0.196
  OccupancyGrid g = ToOccupancy(img, m);
  // occ = (255 - p) / 255: 1.0 -> 100; 0.0039 -> 0; 0.196 -> between -> -1; 0.608 -> between -> -1
  EXPECT_EQ(g.at(0, 0), 100);
  EXPECT_EQ(g.at(1, 0), 0);
  EXPECT_EQ(g.at(2, 0), -1);
  EXPECT_EQ(g.at(3, 0), -1);
  m.mode = MapMode::kScale;
  g = ToOccupancy(img, m);
  EXPECT_EQ(g.at(3, 0), static_cast<std::int8_t>(1 + 98 * ((155.0 / 255.0) - 0.196) / (0.65 - 0.196)));
  m.mode = MapMode::kRaw;
  EXPECT_EQ(ToOccupancy(img, m).at(3, 0), 100);
  m.mode = MapMode::kTrinary;
  m.negate = 1;
  g = ToOccupancy(img, m);
  EXPECT_EQ(g.at(0, 0), 0);
  EXPECT_EQ(g.at(1, 0), 100);
}

TEST(MapServerOccupancyTest, ImageRowZeroIsTheTopOfTheMap) {
  const GreyImage img{1, 2, {0, 254}};  // top black, bottom white
  MapServerMeta m;
  m.resolution_m = 0.5;
  m.origin[0] = 10.0;
  m.origin[1] = 20.0;
  const OccupancyGrid g = ToOccupancy(img, m);
  EXPECT_EQ(g.at(0, 1), 100);
  EXPECT_EQ(g.at(0, 0), 0);
  const Eigen::Vector2d c = g.geometry.CellCenterInMap(0, 1);
  EXPECT_DOUBLE_EQ(c.x(), 10.25);
  EXPECT_DOUBLE_EQ(c.y(), 20.75);
}

}  // namespace
}  // namespace anchordb::engine
