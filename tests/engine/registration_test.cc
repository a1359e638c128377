// ICP on degenerate geometry: a single plane leaves in-plane translation and rotation about the normal unobservable;
// point-to-plane ICP then meets singular normal equations. The result must stay a finite transform (the merge would
// otherwise hand NaN to PCL's kd-tree, whose assertion aborts the server), never a crash.
#include "engine/scene/registration.h"

#include <gtest/gtest.h>

#include <vector>

namespace anchordb::engine {
namespace {

std::vector<Eigen::Vector3f> Wall(float z_m, float shift_x_m) {
  std::vector<Eigen::Vector3f> points;
  for (int v = 0; v < 120; ++v) {
    for (int u = 0; u < 160; ++u) points.emplace_back(-1.0f + u * 0.0125f + shift_x_m, -0.75f + v * 0.0125f, z_m);
  }
  return points;
}

TEST(RegistrationTest, APlaneAloneGivesAFiniteCorrectionOrNone) {
  for (const float shift_x_m : {0.0f, 0.01f, 0.04f}) {
    for (const float dz_m : {0.0f, 0.02f}) {
      const IcpResult r = AlignIcp(Wall(2.0f + dz_m, shift_x_m), Wall(2.0f, 0.0f), IcpParams{});
      EXPECT_TRUE(r.correction.matrix().allFinite()) << "shift " << shift_x_m << " dz " << dz_m;
      EXPECT_TRUE(std::isfinite(r.fitness_m2) || !r.converged);
      if (r.converged) {  // what a plane does determine, the offset along its normal, is corrected
        EXPECT_NEAR(r.correction.translation().z(), -dz_m, 0.005);
      }
    }
  }
}

}  // namespace
}  // namespace anchordb::engine
