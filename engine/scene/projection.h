#pragma once
// Back-projection of depth layers into the map frame (REP-103 optical frame: z forward, x right, y down).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "schema/types.h"

namespace anchordb::engine {

// Points p_map of every pixel with depth > 0 (and mask != 0 when a mask is given), in pixel order.
// `depth_m` is metres per pixel; X_MapCamera is the pose of the optical frame in the map frame.
std::vector<Eigen::Vector3f> BackProject(std::span<const float> depth_m, const PinholeIntrinsics& K,
                                         const Eigen::Isometry3d& X_MapCamera, std::span<const std::uint8_t> mask = {});

// The same from raw sensor units (units_per_m per metre, 0 = none).
std::vector<Eigen::Vector3f> BackProjectRaw(std::span<const std::uint16_t> depth, double units_per_m,
                                            const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera);

Eigen::Isometry3d ToIsometry(const Pose3& pose);

}  // namespace anchordb::engine
