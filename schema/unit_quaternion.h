#pragma once
// A quaternion (x, y, z, w) brought to unit length the one way the project does it: each component divided by the
// norm of (x, y, z, w). Used where a request's pose is parsed (schema/json_io.cc) and where a stored pose enters the
// computations (services/common/stored_pose.h), so both give the same numbers.
#include <Eigen/Geometry>
#include <cmath>

namespace anchordb {

inline double QuaternionNorm(double x, double y, double z, double w) { return std::sqrt(x * x + y * y + z * z + w * w); }

inline Eigen::Quaterniond UnitQuaternion(double x, double y, double z, double w) {
  const double norm = QuaternionNorm(x, y, z, w);
  return Eigen::Quaterniond(w / norm, x / norm, y / norm, z / norm);
}

}  // namespace anchordb
