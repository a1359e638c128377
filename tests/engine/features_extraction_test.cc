#include "engine/features/extraction.h"

#include <gtest/gtest.h>

#include <random>

#include "engine/features/features.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace features_extraction_test {

// A floor (z = 0, 3 x 3 m), a wall (x = 3, 2 m high) and a 0.5 m cube on the floor, sampled every 1 cm with 2 mm
// noise, seen from (0, 0, 1.5).
std::vector<Eigen::Vector3f> Room() {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.002f);
  std::vector<Eigen::Vector3f> pts;
  for (float x = 0; x < 3; x += 0.01f) for (float y = -1.5f; y < 1.5f; y += 0.01f) pts.emplace_back(x, y, noise(rng));
  for (float y = -1.5f; y < 1.5f; y += 0.01f) for (float z = 0; z < 2; z += 0.01f) pts.emplace_back(3 + noise(rng), y, z);
  for (float a = 0; a < 0.5f; a += 0.01f) {
    for (float b = 0; b < 0.5f; b += 0.01f) {
      pts.emplace_back(1.5f + a, b, 0.5f + noise(rng));  // top
      pts.emplace_back(1.5f, b, a);                     // the face towards the sensor
      pts.emplace_back(1.5f + a, 0.0f, b);              // a side
    }
  }
  return pts;
}

TEST(FeatureExtractionTest, PlanesFpfhAndShotOfASyntheticRoom) {
  const auto features = ExtractFeatures(Room(), {0, 0, 1.5}, {"fpfh", "shot", "spd"}, ExtractionParams{});
  int fpfh = 0, shot = 0, spd = 0;
  bool floor = false, wall = false;
  for (const auto& f : features) {
    ASSERT_EQ(static_cast<int>(f.descriptor.size()), *FeatureTypeDims(f.type)) << f.type;
    EXPECT_TRUE(f.anchor_m.x() > -0.2 && f.anchor_m.x() < 3.2 && f.anchor_m.z() > -0.2 && f.anchor_m.z() < 2.2);
    if (f.type == "fpfh") ++fpfh;
    if (f.type == "shot") ++shot;
    if (f.type == "spd") {
      ++spd;
      if (f.descriptor[1] > 0.99f && std::abs(f.descriptor[2]) < 0.02f && f.descriptor[0] > 7.0f) floor = true;  // ~9 m^2
      if (f.descriptor[1] < 0.01f && std::abs(f.anchor_m.x() - 3) < 0.02 && std::abs(f.anchor_m.z() - 1) < 0.05) wall = true;
    }
  }
  EXPECT_TRUE(floor);
  EXPECT_TRUE(wall);
  EXPECT_GE(spd, 2);
  EXPECT_GT(fpfh, 100);  // one per 15 cm voxel of the surfaces
  EXPECT_EQ(fpfh, shot);
  // Only the asked types, and nothing from an empty cloud.
  for (const auto& f : ExtractFeatures(Room(), {0, 0, 1.5}, {"spd"}, ExtractionParams{})) EXPECT_EQ(f.type, "spd");
  EXPECT_TRUE(ExtractFeatures({}, {0, 0, 0}, {"fpfh"}, ExtractionParams{}).empty());
}

TEST(FeatureTypesTest, KnownClientAndUnknownTypes) {
  EXPECT_EQ(FeatureTypeDims("fpfh"), 33);
  EXPECT_EQ(FeatureTypeDims("shot"), 352);
  EXPECT_EQ(FeatureTypeDims("x_color"), std::nullopt);
  EXPECT_THROW(FeatureTypeDims("color"), Error);
  EXPECT_THROW(FeatureTypeDims("x_"), Error);
  EXPECT_THROW(FeatureTypeDims("x_Bad"), Error);
}

TEST(CodebookTest, KMeansSeparatesClustersAndBagsNormalise) {
  std::vector<float> data;
  for (int i = 0; i < 30; ++i) {
    data.push_back(static_cast<float>(i % 3) * 10.0f + 0.01f * static_cast<float>(i));
    data.push_back(0.0f);
  }
  const Codebook book = BuildCodebook(data, 2, 3, 5);
  ASSERT_EQ(book.centres.size(), 6u);
  EXPECT_NE(NearestWord(book, {0.0f, 0.0f}), NearestWord(book, {10.0f, 0.0f}));
  EXPECT_NE(NearestWord(book, {20.0f, 0.0f}), NearestWord(book, {10.0f, 0.0f}));
  EXPECT_EQ(BuildCodebook(data, 2, 3, 5).centres, book.centres);  // seeded
  EXPECT_THROW(BuildCodebook(data, 2, 31, 5), Error);              // more words than descriptors
  const auto h = BagOfWords({0, 0, 1, 2}, 4);
  EXPECT_EQ(h, (std::vector<double>{0.5, 0.25, 0.25, 0.0}));
  EXPECT_EQ(BagOfWords({}, 2), (std::vector<double>{0.0, 0.0}));
  EXPECT_TRUE(InsidePolygon({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, {1, 1}));
  EXPECT_FALSE(InsidePolygon({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, {3, 1}));
}

}  // namespace
}  // namespace anchordb::engine

namespace anchordb::engine {
namespace features_extraction_test {

TEST(CodebookTest, ABagOfOneTypeCodesOnlyThatTypesFeaturesOfTheCodebooksLength) {
  const Codebook book{2, 2, {0.f, 0.f, 10.f, 10.f}};
  const auto feature = [](const char* type, std::vector<float> d) { return ExtractedFeature{type, std::move(d), Eigen::Vector3d::Zero()}; };
  const std::vector<ExtractedFeature> features = {feature("fpfh", {1.f, 1.f}), feature("fpfh", {9.f, 9.f}), feature("fpfh", {9.5f, 9.f}),
                                                  feature("shot", {0.f, 0.f}), feature("fpfh", {0.f, 0.f, 0.f})};
  const TypedBag fpfh = BagOfWordsOfType(features, "fpfh", book);
  EXPECT_EQ(fpfh.coded, 3) << "the shot feature and the 3-value one are not coded";
  ASSERT_EQ(fpfh.bag.size(), 2u);
  EXPECT_NEAR(fpfh.bag[0], 1.0 / 3, 1e-12);
  EXPECT_NEAR(fpfh.bag[1], 2.0 / 3, 1e-12);
  const TypedBag spd = BagOfWordsOfType(features, "spd", book);
  EXPECT_EQ(spd.coded, 0);
  EXPECT_EQ(spd.bag, (std::vector<double>{0.0, 0.0}));
}

}  // namespace
}  // namespace anchordb::engine
