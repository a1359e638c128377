#pragma once
// The multi-layer projection of a 3D occupancy tree into 2D occupancy grids by height band (Hornung et al.'s
// octomap_server multilayer variant: a base band for the mobile base, others for spine and arm). Pure: it works on
// the tree's known leaves (engine/octomap/occupancy_tree.h), not on OctoMap itself. Map frame M, metres.
// A cell is occupied when an occupied leaf overlapping the band covers part of it, free when only free leaves do,
// and unknown (-1) when no known leaf does: unknown stays unknown.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/octomap/occupancy_tree.h"
#include "schema/types.h"

namespace anchordb::engine {

struct HeightBand {
  std::string layer;  // the occupancy layer it becomes
  double min_z_m = 0;
  double max_z_m = 0.3;  // min_z_m < max_z_m
};

// map_server-style cell values: -1 unknown, 0 free, 100 occupied; row-major, iy = 0 at the grid's origin row.
using BandCells = std::vector<std::int8_t>;

// Throws Error(kUnprocessable) for a rotated grid (origin yaw != 0) or an empty / inverted band.
BandCells ProjectBand(const std::vector<Voxel>& known_voxels, float occupied_log_odds, const GridGeometry& grid,
                      const HeightBand& band);

// A grid covering `min_map`..`max_map` in x/y at `resolution_m`, its origin on a multiple of the resolution.
GridGeometry GridCovering(const Eigen::Vector3d& min_map, const Eigen::Vector3d& max_map, double resolution_m);

struct BandCounts {
  std::size_t occupied = 0, free = 0, unknown = 0;
};
BandCounts CountBand(const BandCells& cells);

}  // namespace anchordb::engine
