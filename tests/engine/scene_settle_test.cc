// Movement-settle detection (thesis 3.3.4, engine/scene/settle.h) on hand-made pixel counts.
#include "engine/scene/settle.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace scene_settle_test {

FrameCounts Counts(std::size_t movable, std::size_t reset = 0, std::size_t dynamic = 0) {
  FrameCounts c;
  c.movable = movable;
  c.reset = reset;
  c.dynamic = dynamic;
  return c;
}

// Feeds `frames` frames of the same counts; returns the 1-based frame that settled (0: none).
int FirstSettled(SettleDetector& d, const FrameCounts& c, int frames, const SettleParams& p = {}) {
  for (int i = 1; i <= frames; ++i) {
    if (d.OnFrame(c, p)) return i;
  }
  return 0;
}

TEST(SceneSettleTest, DefaultsAreThoseOfTheSettings) {
  const SettleParams p;
  EXPECT_EQ(p.settle_frames, 8);
  EXPECT_EQ(p.settle_min_change_px, 400);
  EXPECT_EQ(p.settle_tolerance_px, 60);
}

TEST(SceneSettleTest, NothingSettlesWithoutAMovement) {
  SettleDetector d;
  d.OnKeyframe(100);
  EXPECT_EQ(FirstSettled(d, Counts(450), 1), 0);  // no previous frame: not steady
  d.OnKeyframe(450);
  EXPECT_EQ(FirstSettled(d, Counts(450), 50), 0);  // steady, but unchanged since the keyframe
}

TEST(SceneSettleTest, AChangedLayerSettlesAfterSettleFramesSteadyFrames) {
  SettleDetector d;
  d.OnKeyframe(0);
  EXPECT_FALSE(d.OnFrame(Counts(0), {}));
  EXPECT_FALSE(d.OnFrame(Counts(500), {}));  // the movement: a jump, not steady
  // The 8th frame within the tolerance of its predecessor settles (the change since the keyframe is 500 >= 400).
  EXPECT_EQ(FirstSettled(d, Counts(520), 20), 8);
  d.OnKeyframe(520);
  EXPECT_EQ(FirstSettled(d, Counts(520), 20), 0);  // measured from the new keyframe: nothing changed
}

TEST(SceneSettleTest, JustBelowTheMinimumChangeNeverSettles) {
  SettleDetector d;
  d.OnKeyframe(1000);
  d.OnFrame(Counts(1399), {});
  EXPECT_EQ(FirstSettled(d, Counts(1399), 30), 0);
  SettleDetector e;
  e.OnKeyframe(1000);
  e.OnFrame(Counts(1400), {});
  EXPECT_EQ(FirstSettled(e, Counts(1400), 30), 8);
}

TEST(SceneSettleTest, DynamicPixelsAndLargeStepsRestartTheCount) {
  SettleDetector d;
  d.OnKeyframe(0);
  d.OnFrame(Counts(600), {});
  EXPECT_EQ(FirstSettled(d, Counts(600), 5), 0);
  EXPECT_FALSE(d.OnFrame(Counts(600, 0, 1), {}));  // a person in view
  EXPECT_EQ(FirstSettled(d, Counts(600), 7), 0);
  EXPECT_TRUE(d.OnFrame(Counts(600), {}));  // 8 steady frames after the dynamic one
  SettleDetector e;
  e.OnKeyframe(0);
  e.OnFrame(Counts(600), {});
  EXPECT_EQ(FirstSettled(e, Counts(600), 5), 0);
  EXPECT_FALSE(e.OnFrame(Counts(661), {}));  // 61 px more than the previous frame: beyond the tolerance
  EXPECT_EQ(FirstSettled(e, Counts(661), 8), 8);
}

TEST(SceneSettleTest, ARemovalCountsByTheResetPixels) {
  SettleDetector d;
  d.OnKeyframe(0);
  d.OnFrame(Counts(0), {});
  EXPECT_FALSE(d.OnFrame(Counts(0, 300), {}));  // the background behind a removed object is reset farther
  EXPECT_FALSE(d.OnFrame(Counts(0, 100), {}));  // 400 reset since the keyframe; 100 > 60: not steady
  EXPECT_EQ(FirstSettled(d, Counts(0, 10), 20), 8);  // small resets within the tolerance are steady
}

TEST(SceneSettleTest, OffWhenSettleFramesIsZero) {
  SettleParams off;
  off.settle_frames = 0;
  SettleDetector d;
  d.OnKeyframe(0);
  d.OnFrame(Counts(5000), off);
  EXPECT_EQ(FirstSettled(d, Counts(5000), 50, off), 0);
}

}  // namespace
}  // namespace anchordb::engine
