#pragma once
// Occupied voxels as a point cloud at the tree's resolution (the furniture segmentation's input when a map has an
// OctoMap; issue 35: the rule lives in engine/): a pruned voxel (a block of 2^k x 2^k x 2^k equal leaves) gives the
// centre of every leaf it stands for, so the cloud's density does not depend on how the tree was pruned.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "engine/octomap/occupancy_tree.h"

namespace anchordb::engine {

// The leaf centres of `voxels` in the map frame, voxel after voxel. Throws Error(kPayloadTooLarge, field "octomap")
// when they would be more than `max_points`.
std::vector<Eigen::Vector3f> LeafCentres(const std::vector<Voxel>& voxels, double resolution_m, std::size_t max_points);

}  // namespace anchordb::engine
