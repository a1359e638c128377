#pragma once
// A scene model's stored camera pose as the computations use it: renormalised exactly as a request's pose is when it
// is parsed (schema/unit_quaternion.h, as json::AsPose3 does), so the merge, the
// OctoMap feed and the change analysis compute with the same numbers whether the pose came from a request or from
// the store. Responses show the stored numbers unchanged.
#include "schema/types.h"
#include "schema/unit_quaternion.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

inline Pose3 StoredPose(const storage::SceneRecord& scene) {
  const Eigen::Quaterniond& q = scene.pose.orientation;
  Pose3 pose;
  pose.position_m = scene.pose.position_m;
  pose.orientation = UnitQuaternion(q.x(), q.y(), q.z(), q.w());
  return pose;
}

}  // namespace anchordb::services
