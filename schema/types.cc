#include "schema/types.h"

#include <cmath>

namespace anchordb {

double Pose3::YawRad() const {
  const Eigen::Vector3d x_axis_map = orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x_axis_map.y(), x_axis_map.x());
}

Eigen::Vector2d GridGeometry::CellCenterInMap(int ix, int iy) const {
  const double gx = (ix + 0.5) * resolution_m;
  const double gy = (iy + 0.5) * resolution_m;
  const double c = std::cos(origin_yaw_rad), s = std::sin(origin_yaw_rad);
  return {origin_x_m + c * gx - s * gy, origin_y_m + s * gx + c * gy};
}

Eigen::Vector2d GridGeometry::MapToGrid(const Eigen::Vector2d& p_map) const {
  const double dx = p_map.x() - origin_x_m, dy = p_map.y() - origin_y_m;
  const double c = std::cos(origin_yaw_rad), s = std::sin(origin_yaw_rad);
  return {(c * dx + s * dy) / resolution_m, (-s * dx + c * dy) / resolution_m};
}

const char* MapModeName(MapMode mode) {
  switch (mode) {
    case MapMode::kTrinary: return "trinary";
    case MapMode::kScale: return "scale";
    case MapMode::kRaw: return "raw";
  }
  return "trinary";
}

const char* FuseOpName(FuseOp op) {
  switch (op) {
    case FuseOp::kAnd: return "and";
    case FuseOp::kOr: return "or";
    case FuseOp::kAndNot: return "and_not";
    case FuseOp::kXor: return "xor";
  }
  return "and";
}

const char* LayerKindName(LayerKind kind) {
  switch (kind) {
    case LayerKind::kOccupancy: return "occupancy";
    case LayerKind::kProbability: return "probability";
    case LayerKind::kFused: return "fused";
    case LayerKind::kLabel: return "label";
  }
  return "occupancy";
}

}  // namespace anchordb
