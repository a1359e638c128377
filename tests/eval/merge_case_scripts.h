#pragma once
// Internal to tests/eval/merge_case*.cc: the script of a multi-view merge case in a setting, i.e. the true camera
// pose and the scene(s) at every viewpoint, what a perfect system calls movable at the last one, and the checks of
// the construction. merge_case_scripts.cc builds the scripts; merge_cases.cc renders, runs and scores them.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "sim/renderer.h"
#include "tests/eval/merge_cases.h"

namespace anchordb::eval::merge_script {

using Eigen::Isometry3d;

struct Phase {
  Isometry3d X_true;
  sim::Scene first;                  // the scene of the first frames at this viewpoint
  std::optional<sim::Scene> second;  // a change during the observation: the scene from half of the frames on
  const sim::Scene& Last() const { return second ? *second : first; }
};

struct Script {
  std::vector<Phase> phases;
  std::vector<int> expected;                 // objects a perfect system calls movable at the last viewpoint
  std::vector<std::pair<int, int>> hidden;   // (phase, object): must not be seen there (end of the phase)
  std::vector<std::pair<int, int>> shown;    // (phase, object): must be seen there (end of the phase)
  sim::SensorModel sensor;
  double frustum_far_m = 5.0;
  std::ostringstream description;
};

// The script of case `c` in `setting_id` (seed: the setting's variation, sim::MakeSetting). Throws
// std::runtime_error when the case cannot be built in this setting (no suitable place found).
Script BuildScript(sim::Setting setting_id, MergeCase c, std::uint64_t seed, const PinholeIntrinsics& K);

}  // namespace anchordb::eval::merge_script
