#include "engine/events/placement.h"

#include <algorithm>
#include <cmath>

namespace anchordb::engine {

double FootprintDistance(const FurniturePiece& piece, const Eigen::Vector2d& p_m) {
  const double c = std::cos(piece.yaw_rad), s = std::sin(piece.yaw_rad);
  const Eigen::Vector2d d = p_m - piece.position_m;
  const Eigen::Vector2d local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());  // in the piece's own axes
  const Eigen::Vector2d outside = (local.cwiseAbs() - 0.5 * piece.extent_m).cwiseMax(0.0);
  return outside.norm();
}

Placement PlaceObject(const Eigen::Vector3d& object_m, const std::vector<FurniturePiece>& pieces,
                      const grounding::Viewpoint& viewer, double on_margin_m) {
  Placement out;
  const Eigen::Vector2d p = object_m.head<2>();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const double d = FootprintDistance(pieces[i], p);
    if (d < best) best = d, out.piece = static_cast<int>(i);
  }
  if (out.piece < 0) return out;
  out.gap_m = best;
  out.on = best <= on_margin_m;
  const grounding::Distribution4 r =
      grounding::RelationFromOffset(viewer.ToViewer(p - pieces[static_cast<std::size_t>(out.piece)].position_m), 3.0);
  out.relative = static_cast<grounding::Relation>(std::max_element(r.begin(), r.end()) - r.begin());
  return out;
}

}  // namespace anchordb::engine
