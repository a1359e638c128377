#include "engine/grid/attention.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace anchordb::engine {

AttentionResult ComputeAttention(const Agent& person, const std::vector<Region>& regions, const GridGeometry& g,
                                 const AttentionOptions& options) {
  AttentionResult result;
  for (const Region& region : regions) {
    RegionRelation rel;
    rel.region_id = region.id;
    double best = std::numeric_limits<double>::infinity();
    for (int index : region.cells) {
      const Eigen::Vector2d c = g.CellCenterInMap(index % g.width_cells, index / g.width_cells);
      const double d = (c - person.position_m).norm();
      if (d < best) best = d, rel.nearest_m = c;
    }
    rel.distance_m = best;
    if (best <= g.resolution_m * 0.75) {
      rel.facing_angle_rad = 0.0;  // standing on the region: any heading faces it
    } else {
      const Eigen::Vector2d dir = rel.nearest_m - person.position_m;
      rel.facing_angle_rad = std::abs(std::remainder(std::atan2(dir.y(), dir.x()) - person.heading_rad,
                                                     2.0 * std::numbers::pi));
    }
    rel.near = rel.distance_m <= options.near_distance_m;
    rel.facing = rel.facing_angle_rad <= options.max_facing_angle_rad;
    result.relations.push_back(rel);
  }
  std::stable_sort(result.relations.begin(), result.relations.end(),
                   [](const RegionRelation& a, const RegionRelation& b) { return a.distance_m < b.distance_m; });
  for (const RegionRelation& rel : result.relations) {
    if (rel.near && rel.facing) {
      result.attending = true;
      result.attended = rel;
      break;
    }
  }
  return result;
}

}  // namespace anchordb::engine
