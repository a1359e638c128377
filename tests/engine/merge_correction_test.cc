// The merge's localisation rule (engine/scene/merge.h, CorrectedCameraPose): the applied ICP correction with the
// least fitness corrects the camera pose; corrections that were not applied never do.
#include "engine/scene/merge.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace merge_correction_test {

MergeModelReport Model(std::int64_t id, bool applied, double fitness_m2, const Eigen::Vector3d& t_m) {
  MergeModelReport r;
  r.id = id;
  r.icp_applied = applied;
  r.icp.fitness_m2 = fitness_m2;
  r.icp.correction = Eigen::Translation3d(t_m) * Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY());
  return r;
}

TEST(MergeCorrectionTest, TheAppliedCorrectionWithTheLeastFitnessCorrectsTheCamera) {
  MergeResult result;
  result.models = {Model(3, true, 4e-4, {0.02, 0, 0}), Model(5, false, 1e-5, {0.5, 0, 0}),  // better but not applied
                   Model(7, true, 2e-4, {0, 0.03, 0}), Model(9, true, 3e-4, {0, 0, 0.04})};
  const Eigen::Isometry3d X_MC = Eigen::Translation3d(1, 2, 1.3) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  const auto c = CorrectedCameraPose(result, X_MC);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->model_id, 7);
  // X_MC_corrected * correction = X_MC: the correction maps the earlier model onto the current frame.
  const Eigen::Isometry3d back = c->X_MapCamera_corrected * result.models[2].icp.correction;
  EXPECT_TRUE(back.isApprox(X_MC, 1e-12));
}

TEST(MergeCorrectionTest, NoAppliedCorrectionLeavesThePoseAlone) {
  MergeResult result;
  result.models = {Model(3, false, 1e-5, {0.02, 0, 0})};
  EXPECT_FALSE(CorrectedCameraPose(result, Eigen::Isometry3d::Identity()).has_value());
  EXPECT_FALSE(CorrectedCameraPose(MergeResult{}, Eigen::Isometry3d::Identity()).has_value());
}

}  // namespace
}  // namespace anchordb::engine
