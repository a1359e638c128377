// The structured-light input filter of the scene model (SceneModelParams::drop_depth_edges, DepthEdgeMask): depth
// discontinuities larger than theta are left out of Algorithm 1, so flying pixels and wobbling edges of static
// objects do not become movable; smaller steps, surfaces and real changes pass.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "engine/scene/scene_model.h"

namespace anchordb::engine {
namespace depth_edge_filter_test {

constexpr int kW = 12, kH = 8;

// A wall at 2 m with a box at 1 m in columns [4, 8), all rows.
std::vector<std::uint16_t> BoxBeforeWall(int box_u0 = 4, int box_u1 = 8) {
  std::vector<std::uint16_t> d(kW * kH, 2000);
  for (int v = 0; v < kH; ++v) {
    for (int u = box_u0; u < box_u1; ++u) d[v * kW + u] = 1000;
  }
  return d;
}

TEST(DepthEdgeFilterTest, MarksBothSidesOfAJumpAndNothingElse) {
  std::vector<std::uint16_t> d = BoxBeforeWall();
  d[1 * kW + 0] = 2050;  // 2.5 % step on the wall: below theta (3 %), kept
  d[6 * kW + 10] = 0;    // a hole is neither marked nor a partner
  const auto mask = DepthEdgeMask(d, kW, kH, 0.03);
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const bool edge = u == 3 || u == 4 || u == 7 || u == 8;
      EXPECT_EQ(mask[v * kW + u], edge ? 1 : 0) << u << "," << v;
    }
  }
}

TEST(DepthEdgeFilterTest, FlyingPixelsAndAWobblingStaticEdgeDoNotBecomeMovable) {
  SceneModelParams with_filter, without_filter;
  with_filter.drop_depth_edges = true;
  SceneModelState a = NewSceneModel(kW, kH), b = NewSceneModel(kW, kH);
  // Nothing moves; the box's right edge wobbles by a pixel and a flying pixel (1.5 m) sits on its left edge.
  for (int frame = 0; frame < 6; ++frame) {
    std::vector<std::uint16_t> d = BoxBeforeWall(4, frame % 2 == 0 ? 8 : 9);
    if (frame == 5) d[3 * kW + 3] = 1500;
    ApplyFrame(a, d, 1000.0, {}, with_filter);
    ApplyFrame(b, d, 1000.0, {}, without_filter);
  }
  std::size_t movable_without = 0;
  for (std::size_t i = 0; i < a.movable.size(); ++i) {
    EXPECT_EQ(a.movable[i], 0) << "pixel " << i;
    movable_without += b.movable[i];
  }
  // Unfiltered, the column the box covers every other frame and the flying pixel are labelled movable.
  EXPECT_EQ(movable_without, static_cast<std::size_t>(kH) + 1);
}

TEST(DepthEdgeFilterTest, AnObjectThatAppearsIsMovableExceptItsOutermostRing) {
  SceneModelState s = NewSceneModel(kW, kH);
  SceneModelParams params;
  params.drop_depth_edges = true;
  const std::vector<std::uint16_t> wall(kW * kH, 2000);
  ApplyFrame(s, wall, 1000.0, {}, params);
  std::vector<std::uint16_t> d = wall;
  for (int v = 2; v < 7; ++v) {
    for (int u = 3; u < 9; ++u) d[v * kW + u] = 1000;
  }
  const FrameCounts c = ApplyFrame(s, d, 1000.0, {}, params);
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const bool inner = v >= 3 && v < 6 && u >= 4 && u < 8;
      EXPECT_EQ(s.movable[v * kW + u], inner ? 1 : 0) << u << "," << v;
    }
  }
  EXPECT_EQ(c.movable, 12u);
  // The ring of the object (18 px) and the wall pixels touching it (22 px) count as not measured.
  EXPECT_EQ(c.no_depth, 18u + 22u);
  EXPECT_EQ(c.supported, static_cast<std::size_t>(kW * kH) - 12u - 40u);
}

}  // namespace
}  // namespace anchordb::engine
