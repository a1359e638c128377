// Supersession (thesis 3.3.4, engine/scene/supersession.h): distance and optical-axis angle of two camera poses.
#include "engine/scene/supersession.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace scene_supersession_test {

Pose3 At(const Eigen::Vector3d& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Pose3 pose;
  pose.position_m = p;
  pose.orientation = q;
  return pose;
}

Eigen::Quaterniond About(const Eigen::Vector3d& axis, double angle_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, axis.normalized()));
}

TEST(SceneSupersessionTest, DefaultsAreThoseOfTheSettings) {
  const SupersessionParams p;
  EXPECT_DOUBLE_EQ(p.supersede_distance_m, 0.15);
  EXPECT_DOUBLE_EQ(p.supersede_angle_rad, 0.1745);
}

TEST(SceneSupersessionTest, TheSameViewpointSupersedes) {
  const Pose3 old = At({1, 2, 1.2}, About(Eigen::Vector3d::UnitX(), -1.9));
  EXPECT_TRUE(Supersedes(old, old, {}));
}

TEST(SceneSupersessionTest, DistanceLimit) {
  const Pose3 old = At({1, 2, 1.2});
  EXPECT_TRUE(Supersedes(At({1.14, 2, 1.2}), old, {}));
  EXPECT_TRUE(Supersedes(At({1, 2, 1.349}), old, {}));
  EXPECT_FALSE(Supersedes(At({1.16, 2, 1.2}), old, {}));
  EXPECT_TRUE(Supersedes(At({1, 2.1, 1.3}), old, {}));     // 0.141 m (0.1 m in y and in z)
  EXPECT_FALSE(Supersedes(At({1, 2.11, 1.31}), old, {}));  // 0.156 m
}

TEST(SceneSupersessionTest, AngleOfTheOpticalAxesOnly) {
  const Pose3 old = At({0, 0, 1});
  EXPECT_TRUE(Supersedes(At({0, 0, 1}, About(Eigen::Vector3d::UnitY(), 0.17)), old, {}));
  EXPECT_FALSE(Supersedes(At({0, 0, 1}, About(Eigen::Vector3d::UnitY(), 0.18)), old, {}));
  EXPECT_FALSE(Supersedes(At({0, 0, 1}, About(Eigen::Vector3d::UnitX(), -0.18)), old, {}));
  // Rolling about the optical axis (z) keeps the view direction: still the same viewpoint.
  EXPECT_TRUE(Supersedes(At({0, 0, 1}, About(Eigen::Vector3d::UnitZ(), 1.0)), old, {}));
}

TEST(SceneSupersessionTest, ParametersApply) {
  SupersessionParams wide;
  wide.supersede_distance_m = 1.0;
  wide.supersede_angle_rad = 0.5;
  EXPECT_TRUE(Supersedes(At({0.9, 0, 0}, About(Eigen::Vector3d::UnitY(), 0.4)), At({0, 0, 0}), wide));
  EXPECT_FALSE(Supersedes(At({0.9, 0, 0}, About(Eigen::Vector3d::UnitY(), 0.4)), At({0, 0, 0}), {}));
}

}  // namespace
}  // namespace anchordb::engine
