#pragma once
// The JSON of a scene-open request's camera and pose, for the HTTP tests that open scene models.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "schema/types.h"

namespace anchordb::testing {

inline nlohmann::json CameraJson(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

// {"position":[x,y,z],"orientation":[qx,qy,qz,qw]} of a camera pose in the map frame.
inline nlohmann::json PoseJson(const Eigen::Isometry3d& X_MapCamera) {
  const Eigen::Quaterniond q(X_MapCamera.linear());
  return {{"position", {X_MapCamera.translation().x(), X_MapCamera.translation().y(), X_MapCamera.translation().z()}},
          {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

}  // namespace anchordb::testing
