#include "engine/octomap/height_bands.h"

#include <algorithm>
#include <cmath>

#include "schema/error.h"

namespace anchordb::engine {

BandCells ProjectBand(const std::vector<Voxel>& voxels, float occupied_log_odds, const GridGeometry& g,
                      const HeightBand& band) {
  if (g.origin_yaw_rad != 0) {
    throw Error(ErrorCode::kUnprocessable, "a rotated grid (origin yaw != 0) cannot take a height-band projection",
                "like");
  }
  if (!std::isfinite(band.min_z_m) || !std::isfinite(band.max_z_m) || band.min_z_m >= band.max_z_m) {
    throw Error(ErrorCode::kUnprocessable, "a band needs finite min_z_m < max_z_m", "min_z_m");
  }
  BandCells cells(g.CellCount(), -1);
  // A hair inside each footprint, so a leaf flush with a cell border does not mark the neighbour.
  const double eps = 1e-6;
  for (const Voxel& v : voxels) {
    const double half = v.size_m / 2;
    if (v.center_map.z() + half <= band.min_z_m || v.center_map.z() - half >= band.max_z_m) continue;
    const bool occupied = v.log_odds > occupied_log_odds;
    const int x0 = static_cast<int>(std::floor((v.center_map.x() - half + eps - g.origin_x_m) / g.resolution_m));
    const int x1 = static_cast<int>(std::floor((v.center_map.x() + half - eps - g.origin_x_m) / g.resolution_m));
    const int y0 = static_cast<int>(std::floor((v.center_map.y() - half + eps - g.origin_y_m) / g.resolution_m));
    const int y1 = static_cast<int>(std::floor((v.center_map.y() + half - eps - g.origin_y_m) / g.resolution_m));
    for (int iy = std::max(y0, 0); iy <= std::min(y1, g.height_cells - 1); ++iy) {
      for (int ix = std::max(x0, 0); ix <= std::min(x1, g.width_cells - 1); ++ix) {
        std::int8_t& c = cells[static_cast<std::size_t>(iy) * g.width_cells + ix];
        if (occupied) c = 100;
        else if (c != 100) c = 0;
      }
    }
  }
  return cells;
}

GridGeometry GridCovering(const Eigen::Vector3d& min_map, const Eigen::Vector3d& max_map, double resolution_m) {
  GridGeometry g;
  g.resolution_m = resolution_m;
  g.origin_x_m = std::floor(min_map.x() / resolution_m + 1e-9) * resolution_m;
  g.origin_y_m = std::floor(min_map.y() / resolution_m + 1e-9) * resolution_m;
  g.width_cells = std::max(1, static_cast<int>(std::ceil((max_map.x() - g.origin_x_m) / resolution_m - 1e-9)));
  g.height_cells = std::max(1, static_cast<int>(std::ceil((max_map.y() - g.origin_y_m) / resolution_m - 1e-9)));
  return g;
}

BandCounts CountBand(const BandCells& cells) {
  BandCounts c;
  for (std::int8_t v : cells) {
    if (v == 100) ++c.occupied;
    else if (v == 0) ++c.free;
    else ++c.unknown;
  }
  return c;
}

}  // namespace anchordb::engine
