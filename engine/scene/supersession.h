#pragma once
// Supersession (thesis 3.3.4): a scene model opened at (nearly) the viewpoint of an earlier one it merged represents
// that one from then on. Pure.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "schema/types.h"

namespace anchordb::engine {

struct SupersessionParams {
  double supersede_distance_m = 0.15;  // a new model this close ...
  double supersede_angle_rad = 0.1745; // ... looking this similarly supersedes the older one
};

// True when the model whose camera is at X_MapNewer supersedes the earlier one at X_MapOlder: camera positions at
// most supersede_distance_m apart and optical axes (z of the optical frame) at most supersede_angle_rad apart.
inline bool Supersedes(const Pose3& X_MapNewer, const Pose3& X_MapOlder, const SupersessionParams& params) {
  const Eigen::Vector3d view = X_MapNewer.orientation * Eigen::Vector3d::UnitZ();
  const double distance_m = (X_MapOlder.position_m - X_MapNewer.position_m).norm();
  const double angle_rad = std::acos(std::clamp((X_MapOlder.orientation * Eigen::Vector3d::UnitZ()).dot(view), -1.0, 1.0));
  return distance_m <= params.supersede_distance_m && angle_rad <= params.supersede_angle_rad;
}

}  // namespace anchordb::engine
