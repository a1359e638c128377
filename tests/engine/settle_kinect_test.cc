// Movement-settle detection (engine/scene/settle.h) on frames of the Kinect-like sensor (sim/sensor_artefacts):
// Algorithm 1 (scene_model.h) with the depth-edge input filter, fed rendered frames of the sparse room. A static view
// must not look like a movement, and a box put on the floor must settle once.
#include <cstdio>

#include "engine/scene/scene_model.h"
#include "engine/scene/settle.h"
#include "sim/renderer.h"
#include "tests/engine/registration_scenes.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace settle_kinect_test {

namespace rs = registration_scenes;

struct SettleRun {
  std::size_t max_reset = 0, settled_before = 0, settled_after = 0;
  int first_settled_after = 0;
};

SettleRun Observe(const SceneModelParams& params) {
  const PinholeIntrinsics K = rs::Kinect(320, 240);
  sim::Scene scene = rs::SparseRoom();
  SceneModelState state = NewSceneModel(K.width, K.height);
  SettleDetector detector;
  const SettleParams settle;
  SettleRun run;
  for (int i = 0; i < 60; ++i) {
    if (i == 30) {  // a 30 cm box put on the floor beside the table
      scene.objects.push_back({77, "added box", "movable"});
      sim::Primitive box;
      box.object_id = 77;
      box.shape = sim::Shape::kBox;
      box.X_WorldPrim.translation() = Eigen::Vector3d(1.4, 0.35, 0.15);
      box.size_m = Eigen::Vector3d(0.3, 0.3, 0.3);
      scene.primitives.push_back(box);
    }
    const sim::Frame f = sim::Render(scene, K, rs::ViewA(), sim::SensorModel{}, 500 + i);
    const FrameCounts c = ApplyFrame(state, f.depth_mm, 1000.0, {}, params);
    if (i >= 5) run.max_reset = std::max(run.max_reset, c.reset);  // after the first frames filled the model
    if (i == 0) detector.OnKeyframe(c.movable);  // the model's first keyframe
    if (detector.OnFrame(c, settle)) {
      detector.OnKeyframe(c.movable);
      if (i < 30) ++run.settled_before;
      else if (++run.settled_after == 1) run.first_settled_after = i;
    }
  }
  return run;
}

TEST(SceneSettleKinectTest, AStaticViewIsNoMovementAndAnAddedBoxSettlesOnce) {
  // With the depth-edge input filter: without it the sensor's flying pixels and wobbling edges reset 234 background
  // pixels in some frame of every 8 (the tolerance is 60) and the box never settles. The services still run
  // Algorithm 1 without the filter by default (SceneModelParams::drop_depth_edges): an open defect, issue 13's note.
  SceneModelParams params;
  params.drop_depth_edges = true;
  const SettleRun run = Observe(params);
  std::printf("max resets per frame %zu; settled before the box %zu, after %zu (first at frame %d)\n", run.max_reset,
              run.settled_before, run.settled_after, run.first_settled_after);
  EXPECT_EQ(run.settled_before, 0u);
  EXPECT_EQ(run.settled_after, 1u);
  EXPECT_GE(run.first_settled_after, 30 + SettleParams{}.settle_frames);
}

}  // namespace
}  // namespace anchordb::engine
