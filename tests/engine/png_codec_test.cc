// engine/image/png_codec.h (libspng): PNGs written by an independent encoder (sim/png_writer.h, stored deflate)
// decode to the written samples, 16-bit ones in host order; our own PNGs round-trip for every layout we write;
// damaged files are refused, not half-decoded.
#include "engine/image/png_codec.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "sim/png_writer.h"

namespace anchordb::engine {
namespace png_codec_test {

std::vector<std::uint8_t> RandomBytes(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> out(n);
  for (auto& b : out) b = static_cast<std::uint8_t>(rng());
  return out;
}

TEST(PngCodecTest, SixteenBitGreyOfAnotherEncoderDecodesToItsSamples) {
  const std::vector<std::uint16_t> depth_mm = {0, 1, 0x0102, 0xfffe, 4500, 65535};
  const auto png = DecodePngImage(sim::WritePngGrey16(depth_mm, 3, 2));
  ASSERT_TRUE(png);
  EXPECT_EQ(png->width, 3);
  EXPECT_EQ(png->height, 2);
  EXPECT_EQ(png->channels, 1);
  EXPECT_EQ(png->bit_depth, 16);
  std::vector<std::uint16_t> decoded(6);
  ASSERT_EQ(png->bytes.size(), 12u);
  std::memcpy(decoded.data(), png->bytes.data(), 12);
  EXPECT_EQ(decoded, depth_mm);
}

TEST(PngCodecTest, EveryLayoutOfAnotherEncoderAndOfOursRoundTrips) {
  for (int channels = 1; channels <= 4; ++channels) {
    for (int bit_depth : {8, 16}) {
      SCOPED_TRACE(std::to_string(channels) + " channel(s), " + std::to_string(bit_depth) + " bit");
      const int w = 37, h = 11;
      const auto pixels = RandomBytes(static_cast<std::size_t>(w) * h * channels * bit_depth / 8, 7u * channels + bit_depth);
      const auto theirs = DecodePngImage(sim::WritePng(pixels, w, h, channels, bit_depth));
      ASSERT_TRUE(theirs);
      EXPECT_EQ(theirs->channels, channels);
      EXPECT_EQ(theirs->bit_depth, bit_depth);
      EXPECT_EQ(theirs->bytes, pixels);
      const std::string ours = EncodePngImage(PngImage{w, h, channels, bit_depth, pixels}, 1);
      ASSERT_GT(ours.size(), 33u);
      EXPECT_EQ(static_cast<int>(static_cast<std::uint8_t>(ours[24])), bit_depth);  // IHDR bit depth
      const auto back = DecodePngImage(ours);
      ASSERT_TRUE(back);
      EXPECT_EQ(back->bytes, pixels);
    }
  }
}

TEST(PngCodecTest, DamagedOrForeignBytesAreRefusedWithAReason) {
  const std::string good = EncodePngImage(PngImage{16, 16, 1, 16, RandomBytes(512, 3)}, 6);
  ASSERT_TRUE(DecodePngImage(good));
  std::string why;
  EXPECT_FALSE(DecodePngImage("not a png at all", &why));
  EXPECT_FALSE(why.empty());
  for (std::size_t cut : {std::size_t{8}, std::size_t{20}, std::size_t{40}, good.size() - 13, good.size() - 1}) {
    EXPECT_FALSE(DecodePngImage(std::string_view(good).substr(0, cut))) << "cut at " << cut;
  }
  std::string flipped = good;
  flipped[45] = static_cast<char>(flipped[45] ^ 0x5a);  // inside IDAT: its CRC no longer matches
  EXPECT_FALSE(DecodePngImage(flipped, &why));
  // A header of 4000 x 4000 16-bit pixels on a few bytes of data: refused before 32 MB are allocated.
  std::string bomb = sim::WritePng(std::vector<std::uint8_t>(2, 0), 1, 1, 1, 16);
  const char big[8] = {0, 0, 0x0f, static_cast<char>(0xa0), 0, 0, 0x0f, static_cast<char>(0xa0)};
  bomb.replace(16, 8, big, 8);
  std::uint32_t crc = 0xffffffffu;  // the IHDR's CRC (type and data, bytes 12-28) made right again
  for (int i = 12; i < 29; ++i) {
    crc ^= static_cast<std::uint8_t>(bomb[static_cast<std::size_t>(i)]);
    for (int k = 0; k < 8; ++k) crc = (crc & 1u) ? 0xedb88320u ^ (crc >> 1) : crc >> 1;
  }
  crc = ~crc;
  for (int k = 0; k < 4; ++k) bomb[static_cast<std::size_t>(29 + k)] = static_cast<char>((crc >> (24 - 8 * k)) & 0xffu);
  EXPECT_FALSE(DecodePngImage(bomb, &why));
  EXPECT_NE(why.find("more pixels"), std::string::npos) << why;
  // The header's size is read as written, without decoding, also where the decoder refuses the file.
  EXPECT_EQ(PngHeaderSize(bomb), (std::pair<std::uint32_t, std::uint32_t>(4000, 4000)));
  EXPECT_EQ(PngHeaderSize(good), (std::pair<std::uint32_t, std::uint32_t>(16, 16)));
  EXPECT_FALSE(PngHeaderSize(std::string_view(good).substr(0, 23)));
  EXPECT_FALSE(PngHeaderSize("not a png at all, but long enough"));
  EXPECT_THROW(EncodePngImage(PngImage{4, 4, 1, 8, std::vector<std::uint8_t>(15)}), std::invalid_argument);
  EXPECT_THROW(EncodePngImage(PngImage{4, 4, 5, 8, std::vector<std::uint8_t>(80)}), std::invalid_argument);
}

}  // namespace
}  // namespace anchordb::engine
