#pragma once
// Internal to the scene capability: the uncertainty of a scene model's camera pose (issue 13). The client's
// pose_sigma or pose_covariance is checked and resolved into a map-frame covariance (engine::Matrix6d, ROS order
// [tx ty tz rx ry rz], m and rad), stored with the model as 36 numbers (row-major; storage/scene_repository.h), and read back
// for the merge: for the current model's pose and for each earlier model's.
#include <array>
#include <optional>
#include <string>

#include "services/scene/scene_service.h"

namespace anchordb::services::scene_pose {

// The covariance the request gives, or the default of `settings`. Errors name the field: kInvalidArgument for a
// non-finite number; kUnprocessable for both forms given, a negative sigma (or one beyond 10 m / pi rad), a
// covariance that is not 36 numbers, not symmetric, or not positive semi-definite.
engine::Matrix6d Resolve(const OpenSceneRequest& request, const MergeSettings& settings);

// As the scene's record stores it (storage::SceneRecord::pose_covariance: 36 numbers, row-major), and back; nullopt
// when none was stored (models opened before migration 0010) or it was unreadable.
std::array<double, 36> RowMajor(const engine::Matrix6d& covariance);
std::optional<engine::Matrix6d> FromStored(const std::optional<std::array<double, 36>>& row_major);

// The stored covariance, or the default of `settings`.
engine::Matrix6d StoredOrDefault(const std::optional<std::array<double, 36>>& row_major, const MergeSettings& settings);

}  // namespace anchordb::services::scene_pose
