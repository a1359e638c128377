#pragma once
// Point-cloud registration (ICP, PCL) behind plain Eigen types: the only engine interface that PCL sits behind.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace anchordb::engine {

struct IcpParams {
  double voxel_m = 0.03;                    // both clouds are downsampled with a voxel grid of this size first
  double max_correspondence_m = 0.10;       // covers the expected pose error (a few cm, a few degrees) plus noise
  int max_iterations = 40;
  double transformation_epsilon = 1e-8;     // stop when the transform changes less than this (squared)
  double fitness_epsilon = 1e-7;            // stop when the mean squared error changes less than this
  int max_points = 6000;                    // after downsampling, clouds are subsampled evenly to at most this
  double max_range_m = 4.0;                 // points farther from the origin (the current camera) are left out: a
                                            // structured-light sensor's far range is too noisy to register against
};

struct IcpResult {
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  // maps source points onto the target
  bool converged = false;
  double fitness_m2 = 0.0;         // mean squared distance of corresponding points after alignment
  double fitness_before_m2 = 0.0;  // the same before alignment (identity), for judging the result
  std::size_t source_points = 0;
  std::size_t target_points = 0;
};

// Aligns `source` to `target` (both in one frame) starting from the identity.
IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params);

}  // namespace anchordb::engine
