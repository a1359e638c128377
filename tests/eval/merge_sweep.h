#pragma once
// The merge robustness sweep of issue 13 (anchordb_eval_merge --sweep): at every pose error level (the stored pose
// of each viewpoint off by exactly `translation_m` in a random direction and turned by exactly `rotation_rad`
// about a random axis through the optical centre), in a sparse and a cluttered scene (sim/sweep_scenes.h):
//   added: a model built at A (before the object was added) is merged into B's first frame, Algorithm 1 runs on
//          more B frames; the cleaned movable layer (15 x 15, 25 %) is scored against the added object's pixels
//          (transition zone ignored): F1.
//   no change: models built at A and B of the scene after the change (B merging A) are merged into C's first frame,
//          Algorithm 1 runs on more C frames; the fraction of C's measured pixels in the cleaned movable layer.
// Each for the merge (Algorithm 2), the naive strategy (transform + ICP) and no merge (a fresh model).
#include <array>
#include <cstdint>
#include <vector>

#include "engine/scene/merge.h"
#include "sim/sweep_scenes.h"

namespace anchordb::eval {

struct SweepLevel {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};

// The levels: {0, 1, 2, 3, 5} cm x {0, 0.5, 1, 2, 3} deg.
std::vector<SweepLevel> AllSweepLevels();

enum class SweepStrategy { kMerge, kNaive, kNone };
inline constexpr std::array<SweepStrategy, 3> kSweepStrategies = {SweepStrategy::kMerge, SweepStrategy::kNaive,
                                                                 SweepStrategy::kNone};
const char* SweepStrategyName(SweepStrategy s);

struct SweepOptions {
  int frames_a = 4;  // frames of each earlier model
  int frames_b = 4;  // frames after the merged first frame
  int zone_radius_px = 2;
  double pose_sigma_factor = engine::MergeParams{}.pose_sigma_factor;
  std::vector<SweepStrategy> strategies = {kSweepStrategies.begin(), kSweepStrategies.end()};
};

// One seed at one level, per strategy (index as in kSweepStrategies; unrequested ones stay 0).
struct SweepRun {
  std::array<double, 3> added_f1{};
  std::array<double, 3> no_change_fraction{};
  std::size_t added_truth_pixels = 0;
  // The merge's (Algorithm 2's) registrations of this run (3: A into B, A into B and A, B into C for no change):
  int registrations = 0;
  int accepted = 0;
  int fallbacks = 0;  // earlier models not merged (MergeModelReport::fallback)
  // The relative pose error left after registration (the applied correction, else the stored poses), the largest
  // of the run's registrations.
  double left_translation_m = 0.0;
  double left_rotation_rad = 0.0;
};

SweepRun RunSweep(sim::SweepSceneKind kind, const SweepLevel& level, std::uint64_t seed, const SweepOptions& options = {});

// Mean and worst over seeds.
struct SweepSummary {
  int seeds = 0;
  std::array<double, 3> f1_mean{}, f1_worst{};              // worst = lowest
  std::array<double, 3> fraction_mean{}, fraction_worst{};  // worst = highest
  double accepted_fraction = 0.0;
  int fallbacks = 0;
  double left_translation_mean_m = 0.0, left_translation_max_m = 0.0;
  double left_rotation_mean_rad = 0.0, left_rotation_max_rad = 0.0;
};
SweepSummary Summarise(const std::vector<SweepRun>& runs);

// Runs seeds 1..seeds of every level in every scene and prints the table (stdout): per level the added-object F1
// and the no-change movable fraction (mean / worst seed) of merge, naive and no merge, the share of registrations
// accepted, the models not merged, and the relative pose error left (mean / max of the runs' largest).
void PrintSweepTable(const std::vector<sim::SweepSceneKind>& scenes, const std::vector<SweepLevel>& levels, int seeds,
                     const SweepOptions& options);

}  // namespace anchordb::eval
