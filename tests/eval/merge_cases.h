#pragma once
// The multi-view evaluation of thesis 3.5.1 (appendix A cases N0-N1, M0-M9 and the additional settings DO, KI1,
// KI2, SO), rebuilt with the synthetic renderer (issue 4). Each case is a sequence of two phases (three for M9): a
// scene model is built at viewpoint A from a few frames (with changes during the observation where the case says
// so) and closed; the scene may change "meanwhile"; then a new model is opened at viewpoint B: the A model is merged
// into B's first frame (MergeAndApplyFirstFrame, with the strategy under test) and Algorithm 1 runs on more B
// frames. A camera pose error is injected at every viewpoint: the pose stored with a model (and handed to the merge)
// differs from the pose the frames were rendered from. The final movable layer is scored pixel by pixel against the
// renderer's object ids (Table 3.1: cleaned, transition zone ignored).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene/merge.h"
#include "sim/apartment.h"
#include "tests/support/pixel_metrics.h"

namespace anchordb::eval {

enum class MergeCase {
  kN0,   // SE: one object moved (visible) during the observation at A; at the same place at B
  kN1,   // TA: raw scene at A; at B a previously hidden object in front of known background (+ one object moved
         // meanwhile, visible from both, so that there are positives)
  kM0,   // several objects moved (visible) at A; at the same place at B
  kM1,   // raw scene at A; at B a previously hidden object in front of known background; no change (FPR only)
  kM2,   // one object moved and stacked (on another) at A
  kM3,   // two objects moved and stacked at A
  kM4,   // one object moved at A to a place occluded from A; visible at B (occlusion: not expected movable)
  kM5,   // raw scene at A; an object added meanwhile
  kM6,   // raw scene at A; an object removed meanwhile (FPR only)
  kM7,   // raw scene at A; an object added meanwhile at a place occluded from A (not expected movable)
  kM8,   // TA: raw scene at A; a tall object added meanwhile in front of background unknown to A (beyond range)
  kM9,   // TA: three viewpoints A, B, C: an object moved meanwhile to a place occluded from B (visible from A), then
         // seen at the same place from C
  kDO,   // DO: the door leaf (open 30 deg at A) closed meanwhile
  kKI1,  // KI1: the kitchen chair moved meanwhile
  kKI2,  // KI2: the drawer pulled out meanwhile
  kSO,   // SO: a person lies down on the sofa meanwhile
};
const char* MergeCaseName(MergeCase c);
std::vector<MergeCase> AllMergeCases();
// The settings a case runs in (appendix A): N0 SE; N1, M8, M9 TA; M0-M7 TA, SE, CA; DO, KI1, KI2, SO their own.
std::vector<sim::Setting> MergeCaseSettings(MergeCase c);

// The three strategies compared, in this order (index into MergeCaseResult::by_strategy).
inline constexpr std::array<engine::MergeStrategy, 3> kMergeStrategies = {
    engine::MergeStrategy::kAlgorithm2, engine::MergeStrategy::kNaive, engine::MergeStrategy::kNaiveWithoutIcp};
const char* MergeStrategyName(engine::MergeStrategy s);
int StrategyIndex(engine::MergeStrategy s);

// One earlier model merged into a new viewpoint: the pose error the merge had to correct and what ICP left of it.
// Relative pose = the earlier camera in the new one (X_BA). translation: distance between the earlier camera's
// centre as given (stored poses, corrected by ICP when applied) and as it truly was; rotation: angle of R_given R_true^T.
// scene_m: mean displacement of the earlier model's background points (at the scene, ~1-2 m away) between the
// given and the true relative pose.
struct PoseErrorPair {
  double injected_translation_m = 0.0, injected_rotation_rad = 0.0, injected_scene_m = 0.0;  // stored poses
  double translation_m = 0.0, rotation_rad = 0.0, scene_m = 0.0;  // after ICP (= injected if not applied)
  bool icp_converged = false;
  bool icp_applied = false;
  double icp_fitness_m2 = 0.0;
};

struct StrategyResult {
  testing::PixelCounts raw;           // movable layer as computed
  testing::PixelCounts cleaned;       // after the 15 x 15 / 25 % noise cleaning
  testing::PixelCounts cleaned_zone;  // cleaned, transition zone ignored (the figure of 3.5.1)
  std::vector<PoseErrorPair> icp;     // one per merged earlier model (every viewpoint change)
  std::vector<engine::MergeModelReport> reports;
  engine::MergeTiming timing;
  std::size_t unknown_background_detected = 0;  // of MergeCaseResult::unknown_background_pixels, cleaned movable
  // Diagnosis of the false negatives of cleaned_zone (Algorithm 2 only): pixels where the object lies within theta
  // of its own true background (what the last viewpoint would see without the expected-movable objects: Algorithm 1
  // cannot tell them apart, whatever the merge does); of the others, those in front of background no earlier viewpoint
  // measured; then those movable before cleaning; and of the rest
  // the merge's decision at the pixel (MergeDecision; of the earlier model that moved the background back, if any,
  // else of the last one merged).
  std::size_t fn_within_theta = 0;
  std::size_t fn_unknown_background = 0;  // of MergeCaseResult::unknown_background_pixels
  std::size_t fn_cleaned_away = 0;
  std::array<std::size_t, static_cast<std::size_t>(engine::MergeDecision::kCount)> fn_by_decision{};
  // The merge's decision at the false negatives in front of unknown background (fn_unknown_background).
  std::array<std::size_t, static_cast<std::size_t>(engine::MergeDecision::kCount)> fn_unknown_by_decision{};
};

struct MergeCaseResult {
  std::size_t truth_pixels = 0;  // expected-movable pixels with depth in the final frame
  // Truth pixels (outside the transition zone) in front of background that no earlier viewpoint measured: the
  // surface the last viewpoint would see there without the expected-movable objects was beyond the earlier
  // sensor's range, outside its view, hidden or dropped there. M8's point (its wall is beyond A's range).
  std::size_t unknown_background_pixels = 0;
  // Checks of the construction (the case means what appendix A says): pixels (with depth, in the frames of the
  // viewpoint named) of the objects the case needs hidden there (should be ~0), and of the objects it needs seen.
  std::size_t hidden_pixels = 0;
  std::size_t shown_pixels = 0;
  std::string description;  // what was moved where (for the report)
  std::array<StrategyResult, 3> by_strategy;
};

struct MergeCaseOptions {
  int frames_a = 8;  // frames per earlier viewpoint (a change during the observation happens after half of them)
  int frames_b = 8;  // frames after the merged first frame at the last viewpoint
  int zone_radius_px = 2;
  double beta = 0.03;
  double pose_error_translation_m = 0.05;  // uniform magnitude in [0, this], random direction, per viewpoint
  double pose_error_rotation_rad = 0.05235987755982989;  // 3 deg: uniform angle in [0, this], random axis
  double pose_sigma_factor = engine::MergeParams{}.pose_sigma_factor;  // the premises' k (MergeParams)
  std::vector<engine::MergeStrategy> strategies = {kMergeStrategies.begin(), kMergeStrategies.end()};
  // Render with the kind sensor of before issue 13 (no disparity quantisation, correlated noise, jitter, flying
  // pixels or speckle) instead of the Kinect-v1-like default.
  bool kind_sensor = false;
};

// Renders the case once and runs every requested strategy on the same frames (the others stay empty).
// Throws std::runtime_error when the case cannot be built in this setting (no suitable place found).
MergeCaseResult RunMergeCase(sim::Setting setting, MergeCase c, std::uint64_t seed,
                             const MergeCaseOptions& options = {});

}  // namespace anchordb::eval
