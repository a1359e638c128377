#pragma once
// Merging earlier scene models into a new viewpoint (thesis 3.3.2-3.3.3, Algorithm 2, premises 1-3).
// Each earlier model's static background is turned into a point cloud, moved into the new camera by the stored
// poses, refined by ICP against the current frame, rasterised with a z-buffer (nearest wins) and small holes are
// closed; then the accumulated background S_v (initially the current frame) is refined pixel by pixel. The ICP target
// (the current frame, downsampled, with normals and search tree) is prepared once per merge and shared by every
// earlier model; only the sources are downsampled per model (registration.h). The naive
// strategies of the evaluation (transform [+ ICP] + plain Algorithm 1) share the same code path.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/scene/registration.h"
#include "engine/scene/scene_model.h"
#include "schema/types.h"

namespace anchordb::engine {

// An earlier scene model as the merge needs it.
struct PriorModel {
  std::int64_t id = 0;
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();  // as stored (may be off by the localisation error)
  std::vector<float> background_m;                                // its static background, 0 = unknown
  // The uncertainty of X_MapCamera (map frame, registration.h's Matrix6d): the localisation error it may have.
  Matrix6d pose_covariance_map = PoseCovarianceFromSigma(kDefaultPoseSigmaTranslationM, kDefaultPoseSigmaRotationRad);
};

enum class MergeStrategy {
  kAlgorithm2,       // the thesis' merge with premises 1-3 and rear projection
  kNaive,            // transform + ICP, then the z-buffered transformed background is taken as S and Algorithm 1 runs
  kNaiveWithoutIcp,  // the same without ICP
};

struct MergeParams {
  MergeStrategy strategy = MergeStrategy::kAlgorithm2;
  double beta = 0.03;              // noise factor of theta(d) = beta * d, as in Algorithm 1
  double frustum_far_m = 5.0;      // the rear boundary of an earlier model's view frustum (sensor range)
  int neighbourhood_px = 2;        // premise 3 looks at (2r+1)^2 pixels of the transformed model
  int occlusion_px = 4;            // premise 2 looks at (2r+1)^2 pixels of the earlier image at least: dropped-pixel
                                   // slivers (grazing faces, shadows) up to ~2r px wide are not taken for free space
  // The tolerances of premises 1-3, of line 4 and of the rear projection allow for the remaining pose error between
  // the views (issue 13): the remaining uncertainty of the relative pose (IcpResult::covariance, the prior's when the
  // correction is not accepted) is propagated to each pixel's point (merge_tolerance.h), and this many sigmas of its
  // displacement in the images (px) and along the camera z (m) are allowed: line 4 takes the earlier depth within
  // theta (+) that of the current one, premise 1 keeps that far inside the earlier field of view, premise 2 (and the
  // rear projection) requires the earlier camera to have seen nothing at or before the point within that window
  // (radius 2 to 32 px; at least occlusion_px where the earlier pixel itself has no depth) and that margin behind
  // the point.
  double pose_sigma_factor = 2.0;
  // Premise 3 looks this many sigmas of the point's displacement far (at least neighbourhood_px): it only adds to
  // premise 2, which already holds the point's whole (k-sigma) displacement in the earlier image against what that
  // camera saw; wider, it rejects new objects standing next to known ones.
  double neighbourhood_sigma_factor = 1.0;
  // A pixel whose point moves farther than this in an image (k sigma) is not decided from the earlier model (its
  // windows would exceed the largest, 32 px); an earlier model whose median k-sigma displacement exceeds it is not
  // merged at all (MergeModelReport::fallback): the merge is never worse than a fresh model.
  double max_pose_tolerance_px = 32.0;
  int closing_px = 3;              // kernel of the hole-closing after rasterisation
  // Rear projection (lines 9-11): the background moves back along the current ray as far as the earlier camera
  // provably saw free space -- through pixels where it measured something farther, or nothing inside a wide unknown
  // area (beyond the sensor's range) -- up to its frustum's rear boundary (the thesis' P(s_v, V^j), which is where
  // the earlier camera saw nothing at all). An unknown earlier pixel counts only inside a wide unknown area: at least
  // this many pixels from any measured pixel. Narrow unknown areas are dropouts (projector shadow, grazing faces),
  // not evidence of free space.
  double rear_projection_min_unknown_px = 14.0;
  bool record_decisions = false;  // fill MergeModelReport::decisions (Algorithm 2 only)
  IcpParams icp;
  // The uncertainty of the current camera's pose (map frame): with each earlier model's, the prior of the
  // registration (RelativePoseCovariance); the registration decides whether its correction is trusted.
  Matrix6d current_pose_covariance_map =
      PoseCovarianceFromSigma(kDefaultPoseSigmaTranslationM, kDefaultPoseSigmaRotationRad);
};

// What the merge of one earlier model did at a pixel of the new view (MergeParams::record_decisions), for diagnosis.
enum class MergeDecision : std::uint8_t {
  kNothing = 0,            // neither the current frame nor the transformed model has a measurement
  kFilledUnknown,          // the current frame had none: the earlier background fills it
  kSupported,              // line 4
  kNearer,                 // the earlier background is nearer: ignored
  kRejectedFov,            // premise 1
  kRejectedOcclusion,      // premise 2
  kRejectedNeighbourhood,  // premise 3
  kNotSeenThrough,         // lines 6-8: the earlier camera measured nothing behind the point itself
  kReplacedFarther,        // lines 6-8
  kRejectedDropout,        // lines 9-11: the unknown earlier pixel is a dropout next to measured structure
  kRearProjected,          // lines 9-11
  kRearNotBehind,          // lines 9-11: the earlier camera saw no free space (beyond theta) behind the point
  kRejectedUncertain,      // the point's k-sigma displacement exceeds max_pose_tolerance_px: not decided here
  kCount
};

struct MergeModelReport {
  std::int64_t id = 0;
  IcpResult icp;
  bool icp_applied = false;
  std::size_t rasterised_pixels = 0;   // pixels of the current view the transformed model covers
  std::size_t supported = 0;           // line 4: within theta, reliability raised
  std::size_t replaced_farther = 0;    // lines 6-8: background moved back to the earlier model's
  std::size_t rear_projected = 0;      // lines 9-11: unknown in the earlier model -> as far as it saw free space
  std::size_t filled_unknown = 0;      // the current frame had no measurement: the earlier background fills it
  std::size_t rejected_fov = 0;        // premise 1 failed
  std::size_t rejected_occlusion = 0;  // premise 2 failed
  std::size_t rejected_neighbourhood = 0;  // premise 3 failed
  std::size_t rejected_uncertain = 0;      // the pose uncertainty at the pixel was beyond max_pose_tolerance_px
  // The remaining pose uncertainty the premises worked with (MergeParams::pose_sigma_factor sigmas), the median over
  // the earlier model's points: displacement in the current image [px] and along the current camera's z [m].
  double tolerance_px = 0.0;
  double tolerance_m = 0.0;
  // Empty when the model was merged; otherwise why it was not (its pixels are left as a fresh model has them), e.g.
  // the registration was not accepted and the prior is wider than the premises can use.
  std::string fallback;
  std::vector<std::uint8_t> decisions;     // per pixel, a MergeDecision (only with MergeParams::record_decisions)
};

struct MergeTiming {
  double icp_ms = 0.0;
  double rasterise_ms = 0.0;
  double merge_ms = 0.0;
};

struct MergeResult {
  std::vector<MergeModelReport> models;
  MergeTiming timing;
};

// The registration also localises the new camera against the earlier models: the applied ICP correction with the
// least fitness gives the pose the new model's segments are placed with, X_MapCamera * correction^-1 (map frame).
// Nullopt when no correction was applied.
struct CameraCorrection {
  std::int64_t model_id = 0;  // the earlier model whose registration gave it
  Eigen::Isometry3d X_MapCamera_corrected = Eigen::Isometry3d::Identity();
};
std::optional<CameraCorrection> CorrectedCameraPose(const MergeResult& result, const Eigen::Isometry3d& X_MapCamera);

// Builds the initial state of a new scene model at X_MapCamera from the current frame and earlier models, then
// applies the frame with Algorithm 1. `state` must be fresh (NewSceneModel of the current camera).
MergeResult MergeAndApplyFirstFrame(SceneModelState& state, std::span<const std::uint16_t> depth, double units_per_m,
                                    std::span<const std::uint8_t> dynamic_mask, const SceneModelParams& scene_params,
                                    const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera,
                                    const std::vector<PriorModel>& priors, const MergeParams& params);

// Depth image [m] of `points_C` (in the camera frame) with a z-buffer, nearest wins; then holes smaller than the
// closing kernel are filled (OpenCV morphological closing, applied to empty pixels only).
std::vector<float> Rasterise(const std::vector<Eigen::Vector3f>& points_C, const PinholeIntrinsics& K, int closing_px);

// Fraction of `probe_map` points (map frame) that fall into the view frustum of the camera (K, X_MapCamera, far).
double FrustumOverlap(const std::vector<Eigen::Vector3f>& probe_map, const PinholeIntrinsics& K,
                      const Eigen::Isometry3d& X_MapCamera, double far_m);

}  // namespace anchordb::engine
