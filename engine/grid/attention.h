#pragma once
// The attention query of thesis 3.4.3: does a tracked person stand next to a surface region and look toward it?
#include <optional>
#include <vector>

#include "engine/grid/regions.h"

namespace anchordb::engine {

struct AttentionOptions {
  double near_distance_m = 1.0;          // person-to-region distance that counts as "next to"
  double max_facing_angle_rad = 0.7854;  // heading within this angle of the direction to the region's nearest cell
};

struct RegionRelation {
  int region_id = 0;
  double distance_m = 0.0;       // from the person to the nearest cell centre of the region
  double facing_angle_rad = 0.0; // |heading - direction to that cell|, 0 when the person stands on the region
  Eigen::Vector2d nearest_m = Eigen::Vector2d::Zero();
  bool near = false;
  bool facing = false;
};

struct AttentionResult {
  bool attending = false;
  std::optional<RegionRelation> attended;  // the nearest region the person is next to and facing
  std::vector<RegionRelation> relations;   // every region, nearest first
};

AttentionResult ComputeAttention(const Agent& person, const std::vector<Region>& regions, const GridGeometry& geometry,
                                 const AttentionOptions& options);

}  // namespace anchordb::engine
