// Shape models, the size term of verification (engine/shapes/README.md): the size figures of a cloud, two boxes of
// one shape and two sizes told apart by it, and a version-1 blob (no sizes) still read, verifying by votes only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "engine/shapes/shape_model.h"
#include "engine/shapes/virtual_scan.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace shape_size_test {

// A closed box, z up, standing on z = 0.
TriangleMesh Box(float length, float width, float height) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices_m.emplace_back(i & 1 ? length / 2 : -length / 2, i & 2 ? width / 2 : -width / 2, i & 4 ? height : 0.0f);
  }
  const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                            {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const auto& f : faces) m.triangles.emplace_back(f[0], f[1], f[2]);
  return m;
}

std::vector<Eigen::Vector3f> View(const TriangleMesh& mesh, double azimuth_rad) {
  const ScanCamera cam;
  const auto pose = ScanViewpoints(mesh, 1, azimuth_rad, 0.4)[0];
  return DepthToWorldPoints(RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), cam, pose), cam, pose);
}

ShapeModelParams SmallParams() {
  ShapeModelParams p;
  p.codebook_size = 40;
  p.max_keypoints = 200;
  return p;
}

const ShapeModel& TwoBoxes() {
  static const ShapeModel model = [] {
    std::vector<LabelledCloud> samples;
    for (const auto& [category, mesh] : {std::pair{"small", Box(0.5f, 0.4f, 0.6f)}, std::pair{"large", Box(1.0f, 0.8f, 1.2f)}}) {
      for (auto& scan : VirtualScans(mesh, 12, ScanCamera{})) samples.push_back({category, std::move(scan)});
    }
    return TrainShapeModel(samples, SmallParams());
  }();
  return model;
}

// The version-1 layout of a version-2 blob: no size parameters after the seed, no sizes after each category.
std::string ToVersion1(const std::string& v2) {
  std::size_t at = 0;
  std::string out;
  const auto copy = [&](std::size_t n) {
    out.append(v2, at, n);
    at += n;
  };
  const auto u32 = [&] {
    std::uint32_t v;
    std::memcpy(&v, v2.data() + at, 4);
    return v;
  };
  copy(8);
  out.back() = '1';
  copy(9 * 8 + 5 * 4 + 8);  // parameters up to the seed
  at += 3 * 8;              // size_weight, size_bandwidth, size_floor
  copy(4);                  // descriptor length
  const std::uint32_t codebook = u32();
  copy(4 + 4 * static_cast<std::size_t>(codebook));
  const std::uint32_t categories = u32();
  copy(4);
  for (std::uint32_t c = 0; c < categories; ++c) {
    copy(4 + u32());  // name
    copy(8);          // samples, keypoints
    const std::uint32_t words = u32();
    copy(4);
    for (std::uint32_t w = 0; w < words; ++w) copy(4 + 8 * static_cast<std::size_t>(u32()));
    at += 4 + 12 * static_cast<std::size_t>(u32());  // sizes
  }
  EXPECT_EQ(at, v2.size());
  return out;
}

TEST(ShapeSizeTest, SizeFiguresOfARotatedBox) {
  const TriangleMesh box = Box(1.2f, 0.5f, 0.8f);
  std::vector<Eigen::Vector3f> points;
  for (double azimuth : {0.3, 1.9, 3.5, 5.0}) {
    for (const auto& p : View(box, azimuth)) points.push_back(Eigen::AngleAxisf(0.6f, Eigen::Vector3f::UnitZ()) * p);
  }
  const CloudSize size = MeasureCloudSize(points);
  EXPECT_NEAR(size.height_m, 0.8, 0.05);
  EXPECT_NEAR(size.length_m, 1.2, 0.08);
  EXPECT_NEAR(size.width_m, 0.5, 0.05);
  for (const auto& c : TwoBoxes().categories) EXPECT_EQ(c.sizes.size(), static_cast<std::size_t>(c.samples));
}

TEST(ShapeSizeTest, BoxesOfOneShapeAreToldApartByTheirSize) {
  const ShapeModel& model = TwoBoxes();
  for (const auto& [category, mesh] : {std::pair{"small", Box(0.5f, 0.4f, 0.6f)}, std::pair{"large", Box(1.0f, 0.8f, 1.2f)}}) {
    for (double azimuth : {0.4, 2.0, 3.7, 5.4}) {
      const Verification v = Verify(model, View(mesh, azimuth));
      ASSERT_EQ(v.scores.size(), 2u);
      const std::size_t right = v.scores[0].category == category ? 0 : 1;
      EXPECT_GT(v.scores[right].size_log_likelihood, v.scores[1 - right].size_log_likelihood) << category << " " << azimuth;
      EXPECT_EQ(v.best, category) << azimuth;
      EXPECT_NEAR(v.scores[0].probability + v.scores[1].probability, 1.0, 1e-9);
    }
  }
}

TEST(ShapeSizeTest, VersionOneBlobIsReadAndVerifiesByVotesOnly) {
  const std::string v2 = EncodeShapeModel(TwoBoxes());
  EXPECT_EQ(EncodeShapeModel(DecodeShapeModel(v2)), v2);
  const std::string v1 = ToVersion1(v2);
  const ShapeModel old = DecodeShapeModel(v1);
  EXPECT_EQ(old.params.size_weight, 0.0);
  for (const auto& c : old.categories) EXPECT_TRUE(c.sizes.empty());
  ShapeModel votes_only = TwoBoxes();
  votes_only.params.size_weight = 0;
  const auto points = View(Box(0.5f, 0.4f, 0.6f), 1.1);
  const Verification a = Verify(old, points), b = Verify(votes_only, points);
  ASSERT_EQ(a.scores.size(), b.scores.size());
  for (std::size_t i = 0; i < a.scores.size(); ++i) {
    EXPECT_EQ(a.scores[i].weight, b.scores[i].weight);
    EXPECT_EQ(a.scores[i].size_log_likelihood, 0.0);
    EXPECT_DOUBLE_EQ(a.scores[i].probability, b.scores[i].probability);
  }
  for (std::size_t cut : {std::size_t{8}, v1.size() / 2, v1.size() - 1}) {
    EXPECT_THROW(DecodeShapeModel(std::string_view(v1).substr(0, cut)), Error) << cut;
  }
  std::string foreign = v2;
  foreign[7] = '3';
  EXPECT_THROW(DecodeShapeModel(foreign), Error);
}

}  // namespace
}  // namespace anchordb::engine
