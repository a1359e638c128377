#include "engine/grounding/orientation_prior.h"

#include <algorithm>
#include <cmath>

namespace anchordb::engine::grounding {

namespace {

// The piece's own axes in M.
Eigen::Matrix2d Axes(const FurnitureInput& f) {
  const double c = std::cos(f.yaw_rad), s = std::sin(f.yaw_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

// Back to the nearest occupied cell outside the footprint (grown by one cell, where the piece itself may be
// mapped) within reach of it: the side of the footprint it lies beyond gives the back; the front is opposite.
std::optional<Eigen::Vector2d> BackToWall(const FurnitureInput& f, double reach_m, const RoomLayout& room) {
  if (!room.occupancy) return std::nullopt;
  const OccupancyGrid& grid = *room.occupancy;
  const GridGeometry& g = grid.geometry;
  const Eigen::Matrix2d axes = Axes(f);
  const Eigen::Vector2d half = 0.5 * f.extent_m;
  const double grow = g.resolution_m;
  const double radius = half.norm() + reach_m + grow;
  double best_gap = reach_m + grow;
  std::optional<Eigen::Vector2d> back;
  const int span = static_cast<int>(std::ceil(radius / g.resolution_m)) + 1;
  const Eigen::Vector2d centre = g.MapToGrid(f.position_m);
  const int cx = static_cast<int>(std::floor(centre.x())), cy = static_cast<int>(std::floor(centre.y()));
  for (int iy = cy - span; iy <= cy + span; ++iy) {
    for (int ix = cx - span; ix <= cx + span; ++ix) {
      if (!g.Contains(ix, iy) || !IsOccupied(grid.at(ix, iy), room.thresholds)) continue;
      const Eigen::Vector2d local = axes.transpose() * (g.CellCenterInMap(ix, iy) - f.position_m);
      const Eigen::Vector2d beyond = local.cwiseAbs() - half;  // per axis, how far outside the footprint
      if (beyond.maxCoeff() <= grow) continue;                  // inside the grown footprint: the piece itself
      const double gap = beyond.cwiseMax(0.0).norm();
      if (gap >= best_gap) continue;
      best_gap = gap;
      const int axis = beyond.x() >= beyond.y() ? 0 : 1;
      Eigen::Vector2d side = Eigen::Vector2d::Zero();
      side[axis] = local[axis] >= 0.0 ? 1.0 : -1.0;
      back = axes * side;
    }
  }
  if (!back) return std::nullopt;
  return Eigen::Vector2d(-*back);
}

std::optional<Eigen::Vector2d> FacePiece(std::size_t i, const std::string& towards, double reach_m,
                                         const std::vector<FurnitureInput>& furniture, const CategoryTable& categories) {
  const int target = categories.IndexOfId(towards);
  if (target < 0) return std::nullopt;
  double best = 0.0;
  std::optional<Eigen::Vector2d> front;
  for (std::size_t j = 0; j < furniture.size(); ++j) {
    if (j == i || FootprintGap(furniture[i], furniture[j]) > reach_m) continue;
    const double p = furniture[j].category[static_cast<std::size_t>(target)];
    const Eigen::Vector2d d = furniture[j].position_m - furniture[i].position_m;
    if (p > best && d.norm() > 1e-6) {
      best = p;
      front = d.normalized();
    }
  }
  return front;
}

std::optional<Eigen::Vector2d> FaceRoom(std::size_t i, double reach_m, const std::vector<FurnitureInput>& furniture,
                                        const RoomLayout& room) {
  const Eigen::Vector2d p = furniture[i].position_m;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double n = 0.0;
  if (room.occupancy) {
    const GridGeometry& g = room.occupancy->geometry;
    const int span = static_cast<int>(std::ceil(reach_m / g.resolution_m));
    const Eigen::Vector2d centre = g.MapToGrid(p);
    const int cx = static_cast<int>(std::floor(centre.x())), cy = static_cast<int>(std::floor(centre.y()));
    for (int iy = cy - span; iy <= cy + span; ++iy) {
      for (int ix = cx - span; ix <= cx + span; ++ix) {
        if (!g.Contains(ix, iy) || !IsFree(room.occupancy->at(ix, iy), room.thresholds)) continue;
        const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
        if ((c - p).norm() > reach_m) continue;
        sum += c;
        n += 1.0;
      }
    }
  } else {
    for (std::size_t j = 0; j < furniture.size(); ++j) {
      if (j == i || (furniture[j].position_m - p).norm() > reach_m) continue;
      sum += furniture[j].position_m;
      n += 1.0;
    }
  }
  if (n == 0.0) return std::nullopt;
  const Eigen::Vector2d d = sum / n - p;
  if (d.norm() < 0.05) return std::nullopt;  // the room is all around: no direction
  return d.normalized();
}

}  // namespace

Distribution4 OrientationFromFront(const Viewpoint& viewpoint, const Eigen::Vector2d& front_map, double kappa) {
  const Eigen::Vector2d f = viewpoint.ToViewer(front_map).normalized();
  // Directions of the orientations in the viewer frame (x right, y away): left, right, front (towards the viewer),
  // back (away).
  const double cosines[kOrientationCount] = {-f.x(), f.x(), -f.y(), f.y()};
  Distribution4 p{};
  double sum = 0.0;
  for (int o = 0; o < kOrientationCount; ++o) sum += p[static_cast<std::size_t>(o)] = std::exp(kappa * cosines[o]);
  for (double& v : p) v /= sum;
  return p;
}

std::optional<Eigen::Vector2d> FrontDirection(const FrontPrior& rule, std::size_t i, const std::vector<FurnitureInput>& furniture,
                                              const CategoryTable& categories, const RoomLayout& room) {
  switch (rule.rule) {
    case FrontRule::kNone: return std::nullopt;
    case FrontRule::kBackToWall: return BackToWall(furniture[i], rule.reach_m, room);
    case FrontRule::kFacePiece: return FacePiece(i, rule.towards, rule.reach_m, furniture, categories);
    case FrontRule::kFaceRoom: return FaceRoom(i, rule.reach_m, furniture, room);
  }
  return std::nullopt;
}

std::vector<double> RoomOrientationPrior(const Viewpoint& viewpoint, const std::vector<FurnitureInput>& furniture,
                                         const CategoryTable& categories, const RoomLayout& room) {
  std::vector<double> out;
  out.reserve(furniture.size() * kOrientationCount);
  for (std::size_t i = 0; i < furniture.size(); ++i) {
    const auto& pf = furniture[i].category;
    const int label = pf.empty() ? -1 : static_cast<int>(std::max_element(pf.begin(), pf.end()) - pf.begin());
    Distribution4 p = {0.25, 0.25, 0.25, 0.25};
    if (label >= 0 && label < categories.size()) {
      const FrontPrior& rule = categories[label].front;
      if (const auto front = FrontDirection(rule, i, furniture, categories, room)) {
        const Distribution4 q = OrientationFromFront(viewpoint, *front, kFrontSharpness);
        for (std::size_t o = 0; o < kOrientationCount; ++o) p[o] = rule.weight * q[o] + (1.0 - rule.weight) / kOrientationCount;
      }
    }
    double sum = 0.0;
    for (double v : p) sum += v;
    for (double v : p) out.push_back(sum > 0.0 ? v / sum : 1.0 / kOrientationCount);
  }
  return out;
}

}  // namespace anchordb::engine::grounding
