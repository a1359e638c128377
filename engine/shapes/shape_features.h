#pragma once
// Internal to engine/shapes: the local features of a shape model (thesis 4.1.1) behind Eigen / std types. Keypoints
// on boundaries (a point whose normal differs from a neighbour's by more than the boundary angle), topped up by a
// seeded sample of the other points when boundaries are scarce, at most one per keypoint voxel; SHOT descriptors
// (PCL SHOTEstimation) and their local reference frames. Keypoints without a valid frame are dropped.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "engine/shapes/shape_model.h"

namespace anchordb::engine::shapes_detail {

struct LocalFeatures {
  std::vector<Eigen::Vector3f> positions_m;
  std::vector<Eigen::Matrix3f> frames;  // rows: the x, y, z axes of the keypoint's local frame (in the cloud frame)
  std::vector<float> descriptors;       // positions_m.size() x 352, row-major
  int boundary_keypoints = 0;           // how many of them lie on boundaries
};

inline constexpr int kShotDims = 352;

// `points_m` must be finite (checked by the callers).
LocalFeatures ComputeLocalFeatures(const std::vector<Eigen::Vector3f>& points_m, const ShapeModelParams& params,
                                   std::uint64_t seed);

}  // namespace anchordb::engine::shapes_detail
