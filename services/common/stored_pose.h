#pragma once
// A scene model's stored camera pose as the computations use it: renormalised exactly as a request's pose is when it
// is parsed (schema/unit_quaternion.h, as json::AsPose3 does), so the merge, the
// OctoMap feed and the change analysis compute with the same numbers whether the pose came from a request or from
// the store. Responses show the stored numbers unchanged.
#include "schema/types.h"
#include "schema/unit_quaternion.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

inline Pose3 UnitPose(const Pose3& stored) {
  const Eigen::Quaterniond& q = stored.orientation;
  Pose3 pose;
  pose.position_m = stored.position_m;
  pose.orientation = UnitQuaternion(q.x(), q.y(), q.z(), q.w());
  return pose;
}

inline Pose3 StoredPose(const storage::SceneRecord& scene) { return UnitPose(scene.pose); }

}  // namespace anchordb::services
