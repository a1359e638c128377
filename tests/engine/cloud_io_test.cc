// Point clouds in and out through PCL's readers and writers (engine/cloud): every PCD DATA kind and PLY round-trip
// their points; bodies that lie about their size are refused.
#include "engine/cloud/cloud_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "schema/error.h"

namespace anchordb::engine {
namespace cloud_io_test {

std::vector<Eigen::Vector3f> RandomCloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  std::vector<Eigen::Vector3f> points(n);
  for (auto& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

TEST(CloudIo, EveryFormatRoundTripsThePoints) {
  std::vector<Eigen::Vector3f> points = RandomCloud(1000, 3);
  points[10].x() = std::numeric_limits<float>::quiet_NaN();  // organised clouds carry NaN; they pass through
  for (CloudFormat f : {CloudFormat::kPcdAscii, CloudFormat::kPcdBinary, CloudFormat::kPcdBinaryCompressed,
                        CloudFormat::kPlyAscii, CloudFormat::kPlyBinary}) {
    const DecodedCloud back = DecodeCloud(EncodeCloud(points, f), 1 << 20);
    ASSERT_EQ(back.points.size(), points.size()) << static_cast<int>(f);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (i == 10) {
        EXPECT_TRUE(std::isnan(back.points[i].x()));
        continue;
      }
      // ascii keeps PCL's default precision (8 significant digits for PCD, PLY's own for PLY).
      EXPECT_LT((back.points[i] - points[i]).norm(), 1e-5f) << static_cast<int>(f) << " point " << i;
    }
  }
}

TEST(CloudIo, EmptyCloudsRoundTrip) {
  for (CloudFormat f : {CloudFormat::kPcdAscii, CloudFormat::kPcdBinary}) {
    EXPECT_TRUE(DecodeCloud(EncodeCloud({}, f), 10).points.empty());
  }
}

TEST(CloudIo, LyingAndForeignBodiesAreRefused) {
  const std::vector<Eigen::Vector3f> points = RandomCloud(100, 4);
  const std::string binary = EncodeCloud(points, CloudFormat::kPcdBinary);
  EXPECT_THROW(DecodeCloud(binary.substr(0, binary.size() - 13), 1000), Error);
  const std::string compressed = EncodeCloud(points, CloudFormat::kPcdBinaryCompressed);
  EXPECT_THROW(DecodeCloud(compressed.substr(0, compressed.size() - 13), 1000), Error);
  std::string ascii = EncodeCloud(points, CloudFormat::kPcdAscii);
  ascii.replace(ascii.find("POINTS 100"), 10, "POINTS 900");
  EXPECT_THROW(DecodeCloud(ascii, 1000), Error);
  EXPECT_THROW(DecodeCloud(binary, 50), Error);  // over the point limit
  EXPECT_THROW(DecodeCloud("hello", 1000), Error);
  const std::string ply = EncodeCloud(points, CloudFormat::kPlyBinary);
  EXPECT_THROW(DecodeCloud(ply.substr(0, ply.size() - 100), 1000), Error);
}

// PCL reads a header line's numbers by stream extraction, so "1-23T05" is 1 and -23; a negative COUNT wrapped its
// point size and sized a 154 GB buffer before the body was read (found by the fuzz target). Refused as bad input,
// also when the negative number hides inside a word or sits on SIZE or WIDTH.
TEST(CloudIo, NegativeHeaderNumbersAreRefusedBeforePclSizesItsBuffer) {
  const std::string binary = EncodeCloud(RandomCloud(36, 5), CloudFormat::kPcdBinary);
  const auto with = [&binary](const std::string& from, const std::string& to) {
    std::string b = binary;
    const std::size_t at = b.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return b.replace(at, from.size(), to);
  };
  ASSERT_EQ(DecodeCloud(binary, 1000).points.size(), 36u);
  for (const std::string& bad : {with("COUNT 1 1 1", "COUNT 1 1-23T05:30 0"), with("COUNT 1 1 1", "COUNT 1 1 -1"),
                                 with("SIZE 4 4 4", "SIZE 4 4-4 4"), with("WIDTH 36", "WIDTH -36")}) {
    try {
      DecodeCloud(bad, 1000);
      ADD_FAILURE() << "accepted a negative header number";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument) << e.what();
      EXPECT_NE(std::string(e.what()).find("negative"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace anchordb::engine
