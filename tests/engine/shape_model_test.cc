// Shape models (thesis 4.1): training on virtual scans of two meshes, verification of unseen views, detection in a
// scene, the blob round trip, and the errors of bad input.
#include "engine/shapes/shape_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "engine/shapes/virtual_scan.h"
#include "schema/error.h"
#include "tests/support/furniture_meshes.h"

namespace anchordb::engine {
namespace shape_model_test {

ShapeModelParams SmallParams() {
  ShapeModelParams p;
  p.codebook_size = 60;
  p.max_keypoints = 250;
  return p;
}

std::vector<LabelledCloud> Training() {
  std::vector<LabelledCloud> out;
  for (const auto& [category, obj] : {std::pair{"table", testing::TableObj()}, std::pair{"cabinet", testing::CabinetObj()}}) {
    for (auto& scan : VirtualScans(ParseObj(obj), 12, ScanCamera{})) out.push_back({category, std::move(scan)});
  }
  return out;
}

std::vector<Eigen::Vector3f> View(const std::string& obj, double azimuth_rad, double elevation_rad,
                                  const Eigen::Vector3f& offset_m = Eigen::Vector3f::Zero()) {
  const TriangleMesh mesh = ParseObj(obj);
  const ScanCamera cam;
  const auto pose = ScanViewpoints(mesh, 1, azimuth_rad, elevation_rad)[0];
  auto points = DepthToWorldPoints(RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), cam, pose), cam, pose);
  for (auto& p : points) p += offset_m;
  return points;
}

const ShapeModel& Model() {
  static const ShapeModel model = TrainShapeModel(Training(), SmallParams());
  return model;
}

TEST(ShapeModelTest, VerifiesUnseenViewsOfBothCategories) {
  int right = 0, total = 0;
  for (double azimuth : {0.26, 1.3, 2.4, 3.4, 4.5, 5.5}) {
    for (const auto& [category, obj] : {std::pair{"table", testing::TableObj()}, std::pair{"cabinet", testing::CabinetObj()}}) {
      const Verification v = Verify(Model(), View(obj, azimuth, 0.35));
      ASSERT_EQ(v.scores.size(), 2u);
      double sum = 0;
      for (const auto& s : v.scores) sum += s.probability;
      EXPECT_NEAR(sum, 1.0, 1e-9);
      EXPECT_GT(v.keypoints, 10);
      right += v.best == category;
      if (v.best != category) std::cout << category << " at azimuth " << azimuth << " -> " << v.best << "\n";
      ++total;
    }
  }
  EXPECT_GE(right, total - 2) << right << " of " << total;
}

TEST(ShapeModelTest, BlobRoundTripPredictsIdentically) {
  const std::string blob = EncodeShapeModel(Model());
  const ShapeModel back = DecodeShapeModel(blob);
  EXPECT_EQ(EncodeShapeModel(back), blob);
  const auto points = View(testing::TableObj(), 0.8, 0.4);
  const Verification a = Verify(Model(), points), b = Verify(back, points);
  ASSERT_EQ(a.scores.size(), b.scores.size());
  for (std::size_t i = 0; i < a.scores.size(); ++i) EXPECT_EQ(a.scores[i].weight, b.scores[i].weight);
  for (std::size_t cut : {std::size_t{0}, std::size_t{7}, blob.size() / 2, blob.size() - 1}) {
    try {
      DecodeShapeModel(std::string_view(blob).substr(0, cut));
      ADD_FAILURE() << "a blob cut at " << cut << " decoded";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    }
  }
  EXPECT_THROW(DecodeShapeModel(blob + "x"), Error);
}

TEST(ShapeModelTest, DetectsEachPieceNearItsCentre) {
  // Each piece away from the origin with a floor patch around it: the strongest detection names the piece and lies
  // within 0.6 m of its visible points' centroid (horizontally); every detection is >= 75 % of the strongest.
  for (const auto& [category, obj] : {std::pair{"table", testing::TableObj()}, std::pair{"cabinet", testing::CabinetObj()}}) {
    const Eigen::Vector3f offset(3.0f, -1.0f, 0.0f);
    auto scene = View(obj, 0.5, 0.4, offset);
    Eigen::Vector3f centre = Eigen::Vector3f::Zero();
    for (const auto& p : scene) centre += p;
    centre /= static_cast<float>(scene.size());
    for (float x = -1.5f; x <= 1.5f; x += 0.05f) {
      for (float y = -1.5f; y <= 1.5f; y += 0.05f) scene.push_back(offset + Eigen::Vector3f(x, y, 0.0f));
    }
    const auto detections = Detect(Model(), scene);
    ASSERT_FALSE(detections.empty()) << category;
    EXPECT_DOUBLE_EQ(detections.front().relative_weight, 1.0);
    for (const auto& d : detections) EXPECT_GE(d.relative_weight, 0.75);
    EXPECT_EQ(detections.front().category, category);
    EXPECT_LT((detections.front().centre_m - centre).head<2>().norm(), 0.6f)
        << category << " detected at " << detections.front().centre_m.transpose() << ", centroid " << centre.transpose();
  }
}

TEST(ShapeModelTest, BadInputIsRefusedWithTheField) {
  const auto code_of = [](auto&& fn) {
    try {
      fn();
    } catch (const Error& e) {
      return std::pair{e.code(), e.field()};
    }
    return std::pair{ErrorCode::kInternal, std::string("no error")};
  };
  EXPECT_EQ(code_of([] { Verify(Model(), {}); }), std::pair(ErrorCode::kUnprocessable, std::string("points")));
  std::vector<Eigen::Vector3f> nan_cloud = View(testing::TableObj(), 0.3, 0.4);
  nan_cloud[5].y() = std::nanf("");
  EXPECT_EQ(code_of([&] { Verify(Model(), nan_cloud); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(code_of([&] { Detect(Model(), nan_cloud); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(code_of([] { TrainShapeModel({}, SmallParams()); }).first, ErrorCode::kInvalidArgument);
  auto samples = Training();
  samples[3].points_m.clear();
  EXPECT_EQ(code_of([&] { TrainShapeModel(samples, SmallParams()); }),
            std::pair(ErrorCode::kUnprocessable, std::string("samples[3].points")));
  samples = Training();
  samples.push_back({"plinth", std::vector<Eigen::Vector3f>(20, Eigen::Vector3f(1, 1, 1))});  // no keypoint at all
  EXPECT_EQ(code_of([&] { TrainShapeModel(samples, SmallParams()); }).first, ErrorCode::kUnprocessable);
  ShapeModelParams bad = SmallParams();
  bad.azimuth_bins = 0;
  EXPECT_EQ(code_of([&] { TrainShapeModel(Training(), bad); }), std::pair(ErrorCode::kInvalidArgument, std::string("azimuth_bins")));
  EXPECT_EQ(code_of([] { ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(code_of([] { ParseObj("v 0 0 0\nv 1 0 0\nf 1 2\n"); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(code_of([] { ParseObj("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(code_of([] { ParseObj("v 0 0 0\n"); }).first, ErrorCode::kUnprocessable);
  EXPECT_EQ(ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1/1 2/2 4/4 3/3\nf -1 -2 -3\n").triangles.size(), 3u);
}

TEST(ShapeModelTest, TrainingIsDeterministic) {
  EXPECT_EQ(EncodeShapeModel(TrainShapeModel(Training(), SmallParams())), EncodeShapeModel(Model()));
}

}  // namespace
}  // namespace anchordb::engine
