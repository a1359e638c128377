#pragma once
// Point-cloud registration (ICP, PCL) behind plain Eigen types: the only engine interface that PCL sits behind.
// PCL's types stay in registration.cc; a prepared target is an opaque handle.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace anchordb::engine {

// Pose uncertainty: the covariance of a small motion xi = [tx, ty, tz, rx, ry, rz] (m, rad; the order of ROS'
// PoseWithCovariance) applied on the left in the frame the pose is expressed in: X_true = Exp(xi) * X_given.
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The localisation error assumed when a client gives none: AMCL-class (a few cm, a few degrees) per camera pose.
inline constexpr double kDefaultPoseSigmaTranslationM = 0.03;
inline constexpr double kDefaultPoseSigmaRotationRad = 0.035;

// The diagonal covariance of an isotropic error: sigma_translation_m on each axis, sigma_rotation_rad about each.
Matrix6d PoseCovarianceFromSigma(double sigma_translation_m, double sigma_rotation_rad);

// The uncertainty of an earlier camera's pose relative to the current one (X_CurrentEarlier, in the current camera
// frame, as the merge registers it) when each camera's map pose has its own independent error, given as a
// covariance in the map frame (ROS convention). Both poses are camera (optical) frames in the map.
Matrix6d RelativePoseCovariance(const Eigen::Isometry3d& X_MapCurrent, const Matrix6d& covariance_current_map,
                                const Eigen::Isometry3d& X_MapEarlier, const Matrix6d& covariance_earlier_map);

struct IcpParams {
  double voxel_m = 0.03;                    // both clouds are downsampled with a voxel grid of this size first
  double max_correspondence_m = 0.10;       // covers the expected pose error (a few cm, a few degrees) plus noise
  int max_iterations = 40;
  double transformation_epsilon = 1e-7;     // stop when the transform changes less than this (squared; PCL also
                                            // takes 1 - this as the cosine bound of the rotation step)
  double coarse_transformation_epsilon = 1e-6;  // the same for the coarse pass (1 mm, ~0.1 deg): it only has to come
                                                // close, and on some views it otherwise oscillates to max_iterations
  double fitness_epsilon = 1e-7;            // stop when the mean squared error changes less than this
  int max_points = 6000;                    // after downsampling, the target is subsampled evenly to at most this
  int max_source_points = 4000;             // and a source to at most this: every ICP iteration and the fitness
                                            // checks cost one nearest-neighbour search per source point, while the
                                            // target's size only deepens its search tree
  int coarse_source_points = 1500;          // the first, wide-range pass uses an even subset of this many source
                                            // points (it only has to come close); the second, tight pass all of them
  int max_input_points = 80000;             // a cloud is thinned evenly to at most this before the voxel grid (a
                                            // 640x480 image has ~300k points; a 3 cm voxel at 1-4 m still holds
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

IcpTarget PrepareIcpTarget(const std::vector<Eigen::Vector3f>& target, const IcpParams& params);

// Aligns `source` to a prepared target (both in one frame) starting from the identity, with the target's params;
// the relative pose is known up to `prior_covariance` (target frame).
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target,
                   const Matrix6d& prior_covariance);

// The same with the default prior (IcpParams::prior_sigma_*).
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target);

// The same for a one-off target (prepares it, then aligns).
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params);

}  // namespace anchordb::engine
