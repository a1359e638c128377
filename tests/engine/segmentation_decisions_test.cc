// The segmentation service's decisions about a found segment (engine/segmentation/segment_decisions.h): which
// keyframes are its evidence, the prior times the shape model's verification, the running mean of category shares.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "engine/segmentation/segment_decisions.h"

namespace anchordb::engine::segmentation {
namespace segmentation_decisions_test {

constexpr int kWidth = 64, kHeight = 48;

// A camera at the map origin looking along +z (the optical frame is the map frame).
KeyframeView Looking(std::int64_t id, std::uint16_t depth_everywhere_mm) {
  KeyframeView v;
  v.keyframe = id;
  v.K = PinholeIntrinsics{kWidth, kHeight, 50.0, 50.0, 31.5, 23.5};
  v.depth_mm.assign(static_cast<std::size_t>(kWidth * kHeight), depth_everywhere_mm);
  return v;
}

// `n` points at depth z_m on the image's middle row, each on a pixel of its own (column 2 + i).
std::vector<Eigen::Vector3f> Row(int n, double z_m) {
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < n; ++i) {
    const double u = 2 + i + 0.5;  // the pixel centre
    out.emplace_back(static_cast<float>((u - 31.5) * z_m / 50.0), 0.0f, static_cast<float>(z_m));
  }
  return out;
}

std::size_t PixelOf(int column) { return static_cast<std::size_t>(23 * kWidth + column); }

TEST(SegmentEvidenceTest, AKeyframeWhoseDepthMatchesThePointsIsEvidence) {
  EXPECT_EQ(SegmentEvidence(Row(50, 2.0), {Looking(4, 2000)}, 4.0), (std::vector<std::int64_t>{4}));
  EXPECT_EQ(SegmentEvidence(Row(50, 2.0), {Looking(4, 2050)}, 4.0), (std::vector<std::int64_t>{4})) << "5 cm off: seen";
}

TEST(SegmentEvidenceTest, APointHiddenBehindANearerSurfaceOrUnmeasuredIsNotSeen) {
  EXPECT_TRUE(SegmentEvidence(Row(50, 2.0), {Looking(4, 1500)}, 4.0).empty()) << "a surface 0.5 m in front";
  EXPECT_TRUE(SegmentEvidence(Row(50, 2.0), {Looking(4, 0)}, 4.0).empty()) << "no reading";
}

TEST(SegmentEvidenceTest, PointsBeyondRangeOrBehindTheCameraAreNotSeen) {
  EXPECT_TRUE(SegmentEvidence(Row(50, 5.0), {Looking(4, 5000)}, 4.0).empty());
  EXPECT_EQ(SegmentEvidence(Row(50, 5.0), {Looking(4, 5000)}, 6.0), (std::vector<std::int64_t>{4}));
  std::vector<Eigen::Vector3f> behind = Row(50, 2.0);
  for (auto& p : behind) p.z() = -p.z();
  EXPECT_TRUE(SegmentEvidence(behind, {Looking(4, 2000)}, 4.0).empty());
}

TEST(SegmentEvidenceTest, OneInFiveOfTheTriedPointsSeenIsEnough) {
  // 50 points, all tried (step 1); the keyframe measured the right depth at the first k of them only.
  for (const int k : {9, 10}) {
    KeyframeView v = Looking(4, 0);
    for (int i = 0; i < k; ++i) v.depth_mm[PixelOf(2 + i)] = 2000;
    EXPECT_EQ(SegmentEvidence(Row(50, 2.0), {v}, 4.0).size(), k >= 10 ? 1u : 0u) << k << " of 50 seen";
  }
}

TEST(SegmentEvidenceTest, KeyframesComeBackAscendingAndASmallImageIsNotReadPastItsEnd) {
  KeyframeView cut = Looking(2, 2000);
  cut.depth_mm.resize(10);  // fewer pixels than its camera says: nothing measured on the middle row
  EXPECT_EQ(SegmentEvidence(Row(50, 2.0), {Looking(9, 2000), cut, Looking(3, 2000)}, 4.0), (std::vector<std::int64_t>{3, 9}));
}

TEST(PriorTimesVerificationTest, ScoredCategoriesGainUnscoredKeepTheFloorShare) {
  const std::vector<std::string> ids = {"chair", "table"};
  const std::vector<double> p = PriorTimesVerification({0.5, 0.5}, ids, {{"table", 0.9}});
  ASSERT_EQ(p.size(), 2u);
  // chair 0.5 x 0.05, table 0.5 x (0.05 + 0.9), normalised.
  EXPECT_NEAR(p[0], 0.025 / 0.5, 1e-12);
  EXPECT_NEAR(p[1], 0.475 / 0.5, 1e-12);
  const std::vector<double> floor_only = PriorTimesVerification({0.2, 0.8}, ids, {{"sofa", 0.7}});
  EXPECT_NEAR(floor_only[0], 0.2, 1e-12) << "a score for a category outside the ids changes no proportion";
  EXPECT_NEAR(floor_only[1], 0.8, 1e-12);
}

TEST(PriorTimesVerificationTest, NoVoteLeavesThePriorAsItIs) {
  const std::vector<double> prior = {0.1, 0.3};  // not normalised: returned unchanged
  EXPECT_EQ(PriorTimesVerification(prior, {"chair", "table"}, {}), prior);
  EXPECT_EQ(PriorTimesVerification(prior, {"chair", "table"}, {{"chair", 0.0}}), prior);
}

TEST(AverageCategorySharesTest, RunningMeanOverObservations) {
  const std::vector<std::string> ids = {"chair", "table"};
  const auto once = AverageCategoryShares({{"chair", 1.0}}, 1.0, ids, {0.0, 1.0});
  EXPECT_EQ(once, (std::map<std::string, double>{{"chair", 0.5}, {"table", 0.5}}));
  const auto later = AverageCategoryShares({{"chair", 0.5}, {"table", 0.5}, {"plant", 1.0}}, 3.0, ids, {0.2, 0.8});
  EXPECT_NEAR(later.at("chair"), (0.5 * 3 + 0.2) / 4, 1e-12);
  EXPECT_NEAR(later.at("table"), (0.5 * 3 + 0.8) / 4, 1e-12);
  EXPECT_EQ(later.count("plant"), 0u) << "only the knowledge's categories are kept";
}

Footprint Box(double x_m, double y_m, double length_m, double width_m) {
  Footprint f;
  f.centre_m = Eigen::Vector2d(x_m, y_m);
  f.extent_m = Eigen::Vector2d(length_m, width_m);
  f.max_z_m = 0.75;
  return f;
}

TEST(MatchSegmentTest, TheBestOverlapDecidesAtTheThreshold) {
  const Footprint segment = Box(0.0, 0.0, 1.0, 1.0);
  // Overlaps with the segment: 0.5 x 1 of 1.5 (IoU 1/3), 0.8 x 1 of 1.2 (IoU 2/3), none.
  const std::vector<Footprint> known = {Box(0.5, 0.0, 1.0, 1.0), Box(0.2, 0.0, 1.0, 1.0), Box(5.0, 5.0, 1.0, 1.0)};
  const SegmentMatchResult operator_piece = MatchSegment(segment, known, {false, false, true}, 0.5);
  EXPECT_EQ(operator_piece.match, SegmentMatch::kKeepOperatorPiece);
  EXPECT_EQ(operator_piece.index, 1u);
  EXPECT_NEAR(operator_piece.iou, 2.0 / 3.0, 1e-6);
  const SegmentMatchResult perceived = MatchSegment(segment, known, {false, true, false}, 0.5);
  EXPECT_EQ(perceived.match, SegmentMatch::kUpdatePerceivedPiece);
  EXPECT_EQ(perceived.index, 1u);
  // The best overlap below the threshold: a new piece, whatever the others are.
  const SegmentMatchResult below = MatchSegment(segment, known, {true, true, true}, 0.7);
  EXPECT_EQ(below.match, SegmentMatch::kNewPiece);
  EXPECT_NEAR(below.iou, 2.0 / 3.0, 1e-6);
  // At the threshold it matches; with nothing known, or nothing overlapping, it is new.
  EXPECT_EQ(MatchSegment(segment, known, {false, false, false}, operator_piece.iou).match, SegmentMatch::kKeepOperatorPiece);
  EXPECT_EQ(MatchSegment(segment, {}, {}, 0.1).match, SegmentMatch::kNewPiece);
  EXPECT_EQ(MatchSegment(segment, {known[2]}, {true}, 0.0).match, SegmentMatch::kNewPiece);
}

TEST(ParamsForVoxelCentresTest, CoarseVoxelsScaleCountsAndReachAcrossAVoxel) {
  const SegmentationParams p;
  // At or below the thinning voxel nothing changes.
  const SegmentationParams fine = ParamsForVoxelCentres(p, p.voxel_m);
  EXPECT_EQ(fine.voxel_m, p.voxel_m);
  EXPECT_EQ(fine.min_plane_points, p.min_plane_points);
  // 5 cm voxels: every centre its own leaf (half a voxel), counts scaled by the area per point (0.02 / 0.05)^2, and
  // the radii reach 1.5 voxels (7.5 cm) where they were shorter.
  const SegmentationParams coarse = ParamsForVoxelCentres(p, 0.05);
  EXPECT_DOUBLE_EQ(coarse.voxel_m, 0.025);
  EXPECT_EQ(coarse.min_plane_points, static_cast<std::size_t>(std::lround(p.min_plane_points * 0.16)));
  EXPECT_EQ(coarse.min_cluster_points, static_cast<std::size_t>(std::lround(p.min_cluster_points * 0.16)));
  EXPECT_NEAR(coarse.cluster_tolerance_m, 0.075, 1e-12);
  EXPECT_NEAR(coarse.core_radius_m, 0.075, 1e-12);
  EXPECT_NEAR(coarse.outlier_radius_m, 0.075, 1e-12);
  EXPECT_NEAR(coarse.plane_distance_m, std::max(p.plane_distance_m, 0.0375), 1e-12);
  // Very coarse: the counts keep a floor (3 plane points, 1 cluster point) and the reach is capped at 0.5 m.
  const SegmentationParams huge = ParamsForVoxelCentres(p, 4.0);
  EXPECT_EQ(huge.min_plane_points, 3u);
  EXPECT_EQ(huge.min_cluster_points, 1u);
  EXPECT_DOUBLE_EQ(huge.voxel_m, 1.0);
  EXPECT_DOUBLE_EQ(huge.cluster_tolerance_m, 0.5);
  EXPECT_DOUBLE_EQ(huge.plane_distance_m, 0.5);
}

}  // namespace
}  // namespace anchordb::engine::segmentation
