// Segments, keyframe comparison, visibility, matching and placement (engine/events) on constructed depth images.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/events/changes.h"
#include "engine/events/placement.h"
#include "engine/events/segments.h"

namespace anchordb::engine {
namespace events_test {

constexpr int kW = 160, kH = 120;
const PinholeIntrinsics kK{kW, kH, 130.0, 130.0, 79.5, 59.5};

// A wall at 2 m with boxes (pixel rectangles) standing in front of it at the given depths.
struct Rect {
  int u0, v0, u1, v1;
  std::uint16_t mm;
};
std::vector<std::uint16_t> Image(const std::vector<Rect>& rects, std::uint16_t wall_mm = 2000) {
  std::vector<std::uint16_t> d(kW * kH, wall_mm);
  for (const Rect& r : rects) {
    for (int v = r.v0; v < r.v1; ++v) for (int u = r.u0; u < r.u1; ++u) d[v * kW + u] = r.mm;
  }
  return d;
}

ChangeParams SmallParams() {
  ChangeParams p;
  p.segments.min_points = 60;
  return p;
}

TEST(SegmentsTest, TwoObjectsAtDifferentDepthsThatTouchInTheImageAreTwoSegments) {
  // Adjacent in the image but 40 cm apart in depth: region growing on the mask would join them, 3D clustering not.
  const auto depth = Image({{40, 40, 70, 80, 1200}, {70, 40, 100, 80, 1600}});
  const auto background = Image({});
  const auto segments = SegmentMask(InFrontOfBackground(depth, background, SmallParams()), depth, kK,
                                    Eigen::Isometry3d::Identity(), SmallParams());
  ASSERT_EQ(segments.size(), 2u);
  for (const Segment& s : segments) {
    EXPECT_GT(s.points, 900);
    EXPECT_LE(s.sample_m.size(), 256u);
    EXPECT_TRUE(std::abs(s.centroid_m.z() - 1.2) < 0.01 || std::abs(s.centroid_m.z() - 1.6) < 0.01) << s.centroid_m.transpose();
  }
}

TEST(SegmentsTest, ClustersBelowTheSizeThresholdsAreDropped) {
  const auto depth = Image({{10, 10, 14, 14, 1500}, {60, 50, 90, 80, 1500}});
  const auto segments = SegmentMask(InFrontOfBackground(depth, Image({}), SmallParams()), depth, kK,
                                    Eigen::Isometry3d::Identity(), SmallParams());
  ASSERT_EQ(segments.size(), 1u);  // the 4x4 px speck is noise
  EXPECT_NEAR(segments[0].centroid_m.x(), (74.5 - 79.5) / 130.0 * 1.5, 0.01);
}

TEST(ChangesTest, AddedAndRemovedBetweenTwoKeyframesAgainstTheNewerBackground) {
  // Start: object X at the left. End: X gone, object Y at the right. The background at the end is the wall.
  const auto before = Image({{20, 40, 50, 80, 1500}});
  const auto after = Image({{100, 40, 130, 80, 1400}});
  const auto masks = CompareKeyframes(before, after, Image({}), kW, kH, SmallParams());
  const auto count = [](const std::vector<std::uint8_t>& m, int u0, int u1) {
    int n = 0;
    for (int v = 0; v < kH; ++v) for (int u = u0; u < u1; ++u) n += m[v * kW + u];
    return n;
  };
  EXPECT_GT(count(masks.removed, 20, 50), 1000);
  EXPECT_EQ(count(masks.removed, 90, 140), 0);
  EXPECT_GT(count(masks.added, 100, 130), 1000);
  EXPECT_EQ(count(masks.added, 0, 60), 0);
  // An object present at both keyframes (in front of the background both times) is neither.
  const auto both = Image({{60, 40, 90, 80, 1300}});
  const auto same = CompareKeyframes(both, both, Image({}), kW, kH, SmallParams());
  EXPECT_EQ(count(same.added, 0, kW) + count(same.removed, 0, kW), 0);
  // Hidden at the end (something nearer in front, e.g. a person) proves no removal.
  const auto hidden = CompareKeyframes(before, Image({{10, 30, 60, 90, 900}}), Image({}), kW, kH, SmallParams());
  EXPECT_EQ(count(hidden.removed, 0, kW), 0);
}

TEST(ChangesTest, VisibilityOfKnownPointsTellsPresentFromSeenThroughAndHidden) {
  const auto depth = Image({{60, 40, 90, 80, 1500}});
  const auto front = InFrontOfBackground(depth, Image({}), SmallParams());
  const auto points = MaskPoints(front, depth, kK, Eigen::Isometry3d::Identity());
  const Visibility there = CheckVisibility(points, depth, kK, Eigen::Isometry3d::Identity(), SmallParams());
  EXPECT_EQ(there.confirmed, static_cast<int>(points.size()));
  const Visibility gone = CheckVisibility(points, Image({}), kK, Eigen::Isometry3d::Identity(), SmallParams());
  EXPECT_EQ(gone.seen_through, static_cast<int>(points.size()));
  const Visibility hidden = CheckVisibility(points, Image({}, 800), kK, Eigen::Isometry3d::Identity(), SmallParams());
  EXPECT_EQ(hidden.hidden, static_cast<int>(points.size()));
  Eigen::Isometry3d turned = Eigen::Isometry3d::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();  // looking away
  EXPECT_EQ(CheckVisibility(points, depth, kK, turned, SmallParams()).outside, static_cast<int>(points.size()));
}

TEST(ChangesTest, RenderedBackgroundFromTheSamePoseReproducesTheDepth) {
  const auto depth = Image({{60, 40, 90, 80, 1500}});
  std::vector<float> metres(depth.begin(), depth.end());
  for (float& m : metres) m *= 1e-3f;
  std::vector<Eigen::Vector3f> points;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const float z = metres[v * kW + u];
      points.emplace_back(static_cast<float>((u - kK.cx) / kK.fx) * z, static_cast<float>((v - kK.cy) / kK.fy) * z, z);
    }
  }
  const auto rendered = RenderDepthMm(points, kK, Eigen::Isometry3d::Identity());
  int equal = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) equal += std::abs(static_cast<int>(rendered[i]) - depth[i]) <= 1;
  EXPECT_GT(equal, static_cast<int>(depth.size() * 0.97));
}

TEST(MatchingTest, SameObjectMatchesAndSizeSimilarityTellsShapesApart) {
  Segment s;
  s.min_m = {1.0, 1.0, 0.75};
  s.max_m = {1.1, 1.15, 0.95};
  s.centroid_m = 0.5 * (s.min_m + s.max_m);
  EXPECT_TRUE(Matches(s, s.centroid_m + Eigen::Vector3d(0.03, 0.0, 0.0), s.Extent(), MatchParams{}));
  EXPECT_FALSE(Matches(s, s.centroid_m + Eigen::Vector3d(0.30, 0.0, 0.0), s.Extent(), MatchParams{}));
  EXPECT_FALSE(Matches(s, s.centroid_m, Eigen::Vector3d(0.6, 0.6, 0.6), MatchParams{}));  // far larger
  EXPECT_NEAR(SizeSimilarity({0.1, 0.15, 0.2}, {0.15, 0.2, 0.1}), 1.0, 1e-12);  // order does not matter
  EXPECT_LT(SizeSimilarity({0.1, 0.15, 0.2}, {0.2, 0.14, 0.03}), 0.7);          // a flat book is not the box
  EXPECT_GT(SizeSimilarity({0.1, 0.15, 0.2}, {0.09, 0.13, 0.2}), 0.85);          // a partial view of it is
}

TEST(PlacementTest, OnInsideTheFootprintOtherwiseTheRelationSeenFromTheViewer) {
  const std::vector<FurniturePiece> pieces = {{"t", "table", {2.0, 0.0}, {0.8, 1.2}, 0.0},
                                              {"s", "shelf", {0.0, 3.0}, {0.4, 1.0}, M_PI / 2}};
  grounding::Viewpoint viewer;  // at the origin looking along +x: +y is to the viewer's left
  const Placement on = PlaceObject({2.1, 0.3, 0.8}, pieces, viewer);
  EXPECT_EQ(on.piece, 0);
  EXPECT_TRUE(on.on);
  const Placement left = PlaceObject({2.0, 1.0, 0.8}, pieces, viewer);
  EXPECT_EQ(left.piece, 0);
  EXPECT_FALSE(left.on);
  EXPECT_EQ(left.relative, grounding::Relation::kLeftOf);
  EXPECT_NEAR(left.gap_m, 0.4, 1e-9);
  const Placement front = PlaceObject({1.2, 0.0, 0.8}, pieces, viewer);
  EXPECT_EQ(front.relative, grounding::Relation::kInFrontOf);  // between the viewer and the table
  // The shelf is rotated by 90 deg: its 1 m side runs along x.
  EXPECT_NEAR(FootprintDistance(pieces[1], {0.45, 3.0}), 0.0, 1e-9);
  EXPECT_NEAR(FootprintDistance(pieces[1], {0.0, 3.4}), 0.2, 1e-9);
  EXPECT_EQ(PlaceObject({0.0, 0.0, 0.0}, {}, viewer).piece, -1);
}

}  // namespace
}  // namespace anchordb::engine
