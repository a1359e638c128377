#pragma once
// Internal to the scene capability: the uncertainty of a scene model's camera pose (issue 13). The client's
// pose_sigma or pose_covariance is checked and resolved into a map-frame covariance (engine::Matrix6d, ROS order
// [tx ty tz rx ry rz], m and rad), stored with the model as a JSON array of 36 numbers (row-major), and read back
// for the merge: for the current model's pose and for each earlier model's.
#include <optional>
#include <string>

#include "services/scene/scene_service.h"

namespace anchordb::services::scene_pose {

// The covariance the request gives, or the default of `settings`. Errors name the field: kInvalidArgument for a
// non-finite number; kUnprocessable for both forms given, a negative sigma (or one beyond 10 m / pi rad), a
// covariance that is not 36 numbers, not symmetric, or not positive semi-definite.
engine::Matrix6d Resolve(const OpenSceneRequest& request, const MergeSettings& settings);

std::string Document(const engine::Matrix6d& covariance);

// A stored document back; nullopt when none was stored (models opened before migration 0010) or it is unreadable.
std::optional<engine::Matrix6d> FromDocument(const std::string& document);

// The stored covariance, or the default of `settings`.
engine::Matrix6d StoredOrDefault(const std::string& document, const MergeSettings& settings);

}  // namespace anchordb::services::scene_pose
