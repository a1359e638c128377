#pragma once
// A scene model's stored camera pose as the computations use it: renormalised exactly as a request's pose is when it
// is parsed (schema/json_io.h AsPose3: each component divided by the norm of (x, y, z, w)), so the merge, the
// OctoMap feed and the change analysis compute with the same numbers whether the pose came from a request or from
// the store. Responses show the stored numbers unchanged.
#include <cmath>

#include "schema/types.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

inline Pose3 StoredPose(const storage::SceneRecord& scene) {
  const Eigen::Quaterniond& q = scene.pose.orientation;
  const double norm = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
  Pose3 pose;
  pose.position_m = scene.pose.position_m;
  pose.orientation = Eigen::Quaterniond(q.w() / norm, q.x() / norm, q.y() / norm, q.z() / norm);
  return pose;
}

}  // namespace anchordb::services
