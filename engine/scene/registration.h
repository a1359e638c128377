#pragma once
// Point-cloud registration (ICP, PCL) behind plain Eigen types: the only engine interface that PCL sits behind.
// PCL's types stay in registration.cc; a prepared target is an opaque handle.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <span>
#include <vector>

#include "schema/types.h"

namespace anchordb::engine {

// Pose uncertainty: the covariance of a small motion xi = [tx, ty, tz, rx, ry, rz] (m, rad; the order of ROS'
// PoseWithCovariance). A pose in the map (a camera's): as ROS, the position moves by t in the map frame and the
// orientation turns by r about map-frame axes through the pose's own position (R_true = Exp(r) R_given). A relative
// pose X_CurrentEarlier (the registration's): the motion applied on the left in the current camera frame,
// X_true = Exp(xi) * X_given (for the current camera, the origin, both readings agree).
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The localisation error assumed when a client gives none: AMCL-class (a few cm, a few degrees) per camera pose.
inline constexpr double kDefaultPoseSigmaTranslationM = 0.03;
inline constexpr double kDefaultPoseSigmaRotationRad = 0.035;

// The diagonal covariance of an isotropic error: sigma_translation_m on each axis, sigma_rotation_rad about each.
Matrix6d PoseCovarianceFromSigma(double sigma_translation_m, double sigma_rotation_rad);

// The uncertainty of an earlier camera's pose relative to the current one (X_CurrentEarlier, in the current camera
// frame, as the merge registers it) when each camera's map pose has its own independent error, given as a
// covariance in the map frame (ROS convention). Both poses are camera (optical) frames in the map. First order:
// each rotation error is rotated into the current frame, the earlier camera's with its lever arm (the earlier
// camera turns about its own position, d = p_earlier - p_current away from the current frame's origin).
Matrix6d RelativePoseCovariance(const Eigen::Isometry3d& X_MapCurrent, const Matrix6d& covariance_current_map,
                                const Eigen::Isometry3d& X_MapEarlier, const Matrix6d& covariance_earlier_map);

struct IcpParams {
  double voxel_m = 0.02;                    // the target (and the finest source level) is downsampled to this voxel
  // Coarse to fine: the source is aligned at these voxel sizes in turn (the last is voxel_m), each with its own
  // correspondence range: coarse_correspondence_m at the first, halved at each next one, never below
  // min_correspondence_m. The coarse range covers the expected error (5 cm plus 3 deg at 2.5 m is ~18 cm of
  // motion, though only its component along a surface's normal shows in a point-to-plane distance).
  std::array<double, 3> level_voxel_m = {0.08, 0.04, 0.02};
  std::array<int, 3> level_max_points = {400, 900, 1800};   // source points per level at most (evenly thinned)
  // Gauss-Newton steps per level (and start) at most: a level ends earlier when a step is below step_epsilon. The
  // coarse level (400 points) needs the most from a start several degrees off (6 / 6 / 5 left 75 instead of 77 of
  // 80 trials of the sparse room's covariance test inside the 99 % ellipsoid; 30 / 10 / 8 gave no more than 20 / 6 / 5).
  std::array<int, 3> level_iterations = {20, 6, 5};
  double coarse_correspondence_m = 0.15;
  double min_correspondence_m = 0.03;
  double max_correspondence_m = 0.10;       // the range of fitness_m2 / fitness_before_m2 (and the fit test)
  double step_epsilon = 1e-4;               // a level ends when a step moves less than this (m, and rad at 1 m)
  // A pair whose target point lies more than this many target point spacings to the side of the source point
  // (along the target surface) is dropped: the source point lies past the surface's edge.
  double max_side_spacings = 1.5;
  int normal_neighbours = 12;               // target normals from this many nearest neighbours (PCL)
  // Multi-start: besides the prior pose, the coarse level also starts at +-start_sigmas prior standard deviations
  // along the prior's `extra_start_directions` widest (whitened) directions; the start with the lowest MAP cost
  // is refined.
  // A start away from the prior pose wins only with a MAP cost lower by start_margin than the prior pose's.
  int extra_start_directions = 1;
  double start_sigmas = 1.5;
  double start_margin = 3.0;
  double huber_k = 1.5;                     // Huber threshold on residual / sigma (sigma from the sensor model)
  // Directions in which the data's information is below this multiple of the prior's keep the prior pose: the
  // noise of the target's normals alone lends a plane's in-plane directions 5-10 times the prior's information
  // (measured on planes with 1 mm noise, tests/engine/registration_test.cc), which is no observation of them.
  double min_relative_information = 15.0;
  // ... counting only the pairs whose normal has at least this cosine with the displacement a direction moves their
  // point by (registration_solver.h, GeometricInformation): normal noise of a few degrees gives cosines of ~0.05,
  // a surface tilted 15 degrees or more against the motion 0.25 and up.
  double min_normal_alignment = 0.25;
  // RegistrationCloud leaves out pixels whose depth jumps by more than this fraction to a 4-neighbour (0: none).
  double edge_jump_fraction = 0.03;
  // Residual errors are correlated over patches of about this size: the information counts one residual per patch.
  double correlation_patch_m = 0.15;
  // The remaining uncertainty never falls below this (model error: normals, voxel centroids, the sampling of a
  // surface by two viewpoints).
  double floor_sigma_translation_m = 0.002;
  double floor_sigma_rotation_rad = 0.002;
  // Acceptance: the correction's squared Mahalanobis distance under the prior at most this (chi-square, 6 degrees
  // of freedom, 0.999), and at least this fraction of the source points matched within min_correspondence_m.
  double max_mahalanobis2 = 22.46;
  double min_inlier_fraction = 0.2;
  double fit_tolerance = 0.02;              // and the share of the source agreeing with the target at most this
                                            // fraction lower than at the prior pose
  int max_points = 6000;                    // after downsampling, the target is subsampled evenly to at most this
  int max_input_points = 80000;             // a cloud is thinned evenly to at most this before the voxel grid (a
                                            // 640x480 image has ~300k points; a voxel at 1-4 m still holds
                                            // several of the remaining ones, so only the centroids get noisier)
  double max_range_m = 4.0;                 // points farther from the origin (the current camera) are left out: a
                                            // structured-light sensor's far range is too noisy to register against
  // The prior used when the caller gives none, per camera.
  double prior_sigma_translation_m = kDefaultPoseSigmaTranslationM;
  double prior_sigma_rotation_rad = kDefaultPoseSigmaRotationRad;
};

struct IcpResult {
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  // maps source points onto the target
  bool converged = false;
  double fitness_m2 = 0.0;         // mean squared distance of corresponding points after alignment
  double fitness_before_m2 = 0.0;  // the same before alignment (identity), for judging the result
  std::size_t source_points = 0;
  std::size_t target_points = 0;
  // Whether the correction is trusted (the caller applies it only then), and why or why not, for the merge report.
  bool accepted = false;
  std::string verdict;
  // The remaining uncertainty of the relative pose after registration (target frame, as Matrix6d): the prior's
  // when the correction is not accepted.
  Matrix6d covariance = Matrix6d::Zero();
  // Conditioning of the final normal equations: the eigenvalues of the data's information relative to the prior's
  // (whitened by the prior, ascending; 1 = the data knows as much as the prior along that direction), and how many
  // fell below IcpParams::min_relative_information (those directions kept the prior pose).
  std::array<double, 6> relative_information{};
  int unobservable_directions = 0;
  double mahalanobis2 = 0.0;     // of the correction under the prior covariance
  double inlier_fraction = 0.0;  // source points matched within min_correspondence_m at the end
  double residual_rms_m = 0.0;   // point-to-plane, of those matches
  int iterations = 0;            // Gauss-Newton steps over all levels and starts
};

struct IcpTargetData;  // PCL clouds with normals and search trees (defined in registration.cc)

// A target cloud made ready for ICP once (downsampled, normals estimated, search trees built), to align any number
// of source clouds against it: the merge registers every earlier model against the same current frame.
// Cheap to copy (shared, immutable).
struct IcpTarget {
  std::shared_ptr<const IcpTargetData> data;
  IcpParams params;         // the parameters it was prepared with (also used for the sources aligned to it)
  std::size_t points = 0;   // after downsampling, with a valid normal
};

// The points of a depth layer [m per pixel, 0 = none] to register, moved into a frame by X_FrameCamera (optical
// frame of the camera in it): every pixel except those at a depth discontinuity (DepthEdgeMask with
// edge_jump_fraction; 0 keeps all). There a structured-light sensor reports flying depths between the two surfaces
// and edges that wobble by a pixel; point-to-plane pairs on them pull the fit sideways along the object's sides
// (the sparse room's covariance test: 72 -> 75 of 80 trials inside the 99 % ellipsoid with them left out).
std::vector<Eigen::Vector3f> RegistrationCloud(std::span<const float> depth_m, const PinholeIntrinsics& K,
                                               const Eigen::Isometry3d& X_FrameCamera, double edge_jump_fraction);

IcpTarget PrepareIcpTarget(const std::vector<Eigen::Vector3f>& target, const IcpParams& params);

// Aligns `source` to a prepared target (both in one frame) starting from the identity, with the target's params;
// the relative pose is known up to `prior_covariance` (target frame, a left motion, positive semi-definite):
// point-to-plane Gauss-Newton MAP (robust Huber kernel, coarse to fine, multi-start at the coarse level) whose
// directions the data cannot observe keep the prior. The correction is accepted when the fit improves, enough of
// the source matches, and it is consistent with the prior (chi-square bound); `verdict` says which.
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target,
                   const Matrix6d& prior_covariance);

// The same with the default prior (IcpParams::prior_sigma_*).
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target);

// The same for a one-off target (prepares it, then aligns).
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params);

}  // namespace anchordb::engine
