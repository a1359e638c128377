// Algorithm 1 (thesis 3.2.3) on hand-made pixels: every branch, both dynamic-region variants, zero depth.
#include "engine/scene/scene_model.h"

#include <gtest/gtest.h>

#include "engine/scene/projection.h"

namespace anchordb::engine {
namespace scene_model_test {

// A 1 x n image helper: depths in mm.
FrameCounts Feed(SceneModelState& s, std::vector<std::uint16_t> mm, std::vector<std::uint8_t> dyn = {},
                 DynamicMode mode = DynamicMode::kExcludeFromInput) {
  SceneModelParams p;
  p.dynamic_mode = mode;
  p.drop_depth_edges = false;  // Algorithm 1 alone; the input filter has its own tests (DepthEdgeFilterTest)
  return ApplyFrame(s, mm, 1000.0, dyn, p);
}

TEST(AlgorithmOneTest, FirstMeasurementResetsUnknownBackground) {
  SceneModelState s = NewSceneModel(2, 1);
  const auto c = Feed(s, {2000, 0});
  EXPECT_EQ(c.reset, 1u);
  EXPECT_EQ(c.no_depth, 1u);
  EXPECT_FLOAT_EQ(s.background_m[0], 2.0f);
  EXPECT_FLOAT_EQ(s.weight[0], 1.0f);
  EXPECT_FLOAT_EQ(s.background_m[1], 0.0f);  // s_0 = 0 stays: nothing measured
  EXPECT_EQ(s.frames, 1);
}

TEST(AlgorithmOneTest, SupportingMeasurementUpdatesRunningMeanAndWeight) {
  SceneModelState s = NewSceneModel(1, 1);
  Feed(s, {2000});
  // theta(2.0) = 0.06 m: 2.04 is within, so s = 2.0 + (2.04 - 2.0) / 1, w = 2
  auto c = Feed(s, {2040});
  EXPECT_EQ(c.supported, 1u);
  EXPECT_NEAR(s.background_m[0], 2.04, 1e-6);
  EXPECT_FLOAT_EQ(s.weight[0], 2.0f);
  // next: s = 2.04 + (2.01 - 2.04) / 2 = 2.025, w = 3
  Feed(s, {2010});
  EXPECT_NEAR(s.background_m[0], 2.025, 1e-6);
  EXPECT_FLOAT_EQ(s.weight[0], 3.0f);
  EXPECT_EQ(s.movable[0], 0);
}

TEST(AlgorithmOneTest, FartherMeasurementResetsBackgroundAndWeight) {
  SceneModelState s = NewSceneModel(1, 1);
  Feed(s, {1500});
  Feed(s, {1500});
  EXPECT_FLOAT_EQ(s.weight[0], 2.0f);
  const auto c = Feed(s, {1700});  // 0.2 m farther: beyond theta(1.5) = 0.045
  EXPECT_EQ(c.reset, 1u);
  EXPECT_FLOAT_EQ(s.background_m[0], 1.7f);
  EXPECT_FLOAT_EQ(s.weight[0], 1.0f);
  EXPECT_EQ(s.movable[0], 0);
}

TEST(AlgorithmOneTest, NearerMeasurementIsMovableAndKeepsBackground) {
  SceneModelState s = NewSceneModel(1, 1);
  Feed(s, {2000});
  Feed(s, {2000});
  const auto c = Feed(s, {1800});
  EXPECT_EQ(c.movable, 1u);
  EXPECT_EQ(s.movable[0], 1);
  EXPECT_FLOAT_EQ(s.background_m[0], 2.0f);
  EXPECT_FLOAT_EQ(s.weight[0], 2.0f);
  // The object goes away: the background is seen again and the pixel is no longer movable.
  Feed(s, {2000});
  EXPECT_EQ(s.movable[0], 0);
}

TEST(AlgorithmOneTest, ThresholdIsProportionalToDepth) {
  SceneModelState s = NewSceneModel(2, 1);
  Feed(s, {1000, 4000});
  // 2.5 cm nearer: inside theta(1.0) = 3 cm; 10 cm nearer at 4 m: inside theta(4.0) = 12 cm.
  Feed(s, {975, 3900});
  EXPECT_EQ(s.movable[0], 0);
  EXPECT_EQ(s.movable[1], 0);
  SceneModelState t = NewSceneModel(2, 1);
  Feed(t, {1000, 4000});
  // 4 cm nearer at 1 m and 15 cm nearer at 4 m: movable.
  Feed(t, {960, 3850});
  EXPECT_EQ(t.movable[0], 1);
  EXPECT_EQ(t.movable[1], 1);
}

TEST(AlgorithmOneTest, ZeroDepthUpdatesNothing) {
  SceneModelState s = NewSceneModel(1, 1);
  Feed(s, {2000});
  Feed(s, {1500});  // movable
  const SceneModelState before = s;
  const auto c = Feed(s, {0});
  EXPECT_EQ(c.no_depth, 1u);
  EXPECT_EQ(s.background_m, before.background_m);
  EXPECT_EQ(s.weight, before.weight);
  EXPECT_EQ(s.movable, before.movable);  // the last measured label stands
}

TEST(AlgorithmOneTest, ExcludeModeDynamicPixelsAreLeftOutOfTheInput) {
  SceneModelState s = NewSceneModel(3, 1);
  Feed(s, {2000, 2000, 2000});
  // Pixel 0: a person (nearer) inside D: not movable, labelled dynamic, background untouched.
  // Pixel 1: farther inside D: would reset, but is excluded.  Pixel 2: nearer outside D: movable.
  const auto c = Feed(s, {1200, 2500, 1500}, {1, 1, 0});
  EXPECT_EQ(s.dynamic, (std::vector<std::uint8_t>{1, 1, 0}));
  EXPECT_EQ(s.movable, (std::vector<std::uint8_t>{0, 0, 1}));
  EXPECT_FLOAT_EQ(s.background_m[1], 2.0f);
  EXPECT_FLOAT_EQ(s.weight[0], 1.0f);
  EXPECT_EQ(c.dynamic, 2u);
  EXPECT_EQ(c.movable, 1u);
}

TEST(AlgorithmOneTest, SubtractModeFollowsEquations34And35) {
  SceneModelState s = NewSceneModel(4, 1);
  Feed(s, {2000, 2000, 2000, 2000}, {}, DynamicMode::kSubtractFromMovable);
  // 0: nearer & in D -> dynamic (O ∩ D); 1: nearer, not in D -> movable (O \ D);
  // 2: static but in D (a tracker false positive) -> neither, and the background is updated;
  // 3: farther & in D -> background reset (F_t is used whole), neither label.
  Feed(s, {1200, 1500, 2010, 2600}, {1, 0, 1, 1}, DynamicMode::kSubtractFromMovable);
  EXPECT_EQ(s.dynamic, (std::vector<std::uint8_t>{1, 0, 0, 0}));
  EXPECT_EQ(s.movable, (std::vector<std::uint8_t>{0, 1, 0, 0}));
  EXPECT_FLOAT_EQ(s.weight[2], 2.0f);
  EXPECT_FLOAT_EQ(s.background_m[3], 2.6f);
}

TEST(AlgorithmOneTest, DepthScaleForOtherConventions) {
  SceneModelState s = NewSceneModel(1, 1);
  SceneModelParams p;
  const std::vector<std::uint16_t> tum = {10000};  // TUM: 5000 per metre -> 2 m
  ApplyFrame(s, tum, 5000.0, {}, p);
  EXPECT_FLOAT_EQ(s.background_m[0], 2.0f);
}

TEST(CleanMovableTest, IsolatedPixelsGoBlobsStay) {
  const int w = 40, h = 30;
  std::vector<std::uint8_t> m(w * h, 0);
  m[5 * w + 5] = 1;                                                     // isolated noise
  for (int y = 10; y < 22; ++y) for (int x = 20; x < 32; ++x) m[y * w + x] = 1;  // 12 x 12 object
  const auto c = CleanMovable(m, w, h);
  EXPECT_EQ(c[5 * w + 5], 0);
  EXPECT_EQ(c[15 * w + 25], 1);
  // A corner of the blob sees 8 x 8 - 1 = 63 movable others of 224 (28 %): kept.
  EXPECT_EQ(c[10 * w + 20], 1);
  // A 2-pixel-wide streak (an edge artefact) sees at most 2 x 15 - 1 = 29 (13 %): removed.
  std::vector<std::uint8_t> streak(w * h, 0);
  for (int x = 5; x < 35; ++x) streak[2 * w + x] = streak[3 * w + x] = 1;
  const auto cs = CleanMovable(streak, w, h);
  EXPECT_EQ(std::count(cs.begin(), cs.end(), 1), 0);
  // Brute force agreement over the whole image.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!m[y * w + x]) {
        EXPECT_EQ(c[y * w + x], 0);
        continue;
      }
      int n = -1;
      for (int dy = -7; dy <= 7; ++dy) for (int dx = -7; dx <= 7; ++dx) {
        const int yy = y + dy, xx = x + dx;
        if (yy >= 0 && yy < h && xx >= 0 && xx < w) n += m[yy * w + xx];
      }
      EXPECT_EQ(c[y * w + x], n >= 0.25 * 224 ? 1 : 0) << x << "," << y;
    }
  }
}

TEST(ProjectionTest, BackProjectionUsesOpticalFrameAndPose) {
  PinholeIntrinsics K{4, 2, 2.0, 2.0, 1.5, 0.5};
  std::vector<float> depth(8, 0.0f);
  depth[0] = 2.0f;          // u 0, v 0
  depth[1 * 4 + 3] = 1.0f;  // u 3, v 1
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(10, 20, 30);
  const auto pts = BackProject(depth, K, X);
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_TRUE(pts[0].isApprox(Eigen::Vector3f(10 + (0 - 1.5f) / 2 * 2, 20 + (0 - 0.5f) / 2 * 2, 32), 1e-6f));
  EXPECT_TRUE(pts[1].isApprox(Eigen::Vector3f(10 + 1.5f / 2, 20 + 0.5f / 2, 31), 1e-6f));
  // A camera looking along map +x (optical z -> map x, optical x -> map -y, optical y -> map -z).
  Eigen::Isometry3d look_x = Eigen::Isometry3d::Identity();
  look_x.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const auto p = BackProject(depth, K, look_x);
  EXPECT_NEAR(p[0].x(), 2.0f, 1e-6f);
  EXPECT_NEAR(p[0].y(), 1.5f, 1e-6f);
  EXPECT_NEAR(p[0].z(), 0.5f, 1e-6f);
}

}  // namespace
}  // namespace anchordb::engine
