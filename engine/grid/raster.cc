#include "engine/grid/raster.h"

#include <algorithm>
#include <cmath>

namespace anchordb::engine {

std::size_t RasterisePolygons(const std::vector<Polygon2>& polygons_map, MaskGrid& mask) {
  const GridGeometry& g = mask.geometry;
  std::size_t set = 0;
  std::vector<double> crossings;
  for (const Polygon2& polygon : polygons_map) {
    std::vector<Eigen::Vector2d> v;  // vertices in continuous grid coordinates [cells]
    v.reserve(polygon.size());
    double min_y = 1e300, max_y = -1e300;
    for (const auto& p : polygon) {
      v.push_back(g.MapToGrid(p));
      min_y = std::min(min_y, v.back().y());
      max_y = std::max(max_y, v.back().y());
    }
    const int iy0 = std::max(0, static_cast<int>(std::floor(min_y - 0.5)));
    const int iy1 = std::min(g.height_cells - 1, static_cast<int>(std::ceil(max_y - 0.5)));
    for (int iy = iy0; iy <= iy1; ++iy) {
      const double yc = iy + 0.5;
      crossings.clear();
      for (std::size_t k = 0; k < v.size(); ++k) {
        const Eigen::Vector2d& a = v[k];
        const Eigen::Vector2d& b = v[(k + 1) % v.size()];
        if ((a.y() <= yc) != (b.y() <= yc)) crossings.push_back(a.x() + (yc - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
      }
      std::sort(crossings.begin(), crossings.end());
      for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
        // cells with centre x + 0.5 in (x_in, x_out)
        const int ix0 = std::max(0, static_cast<int>(std::ceil(crossings[k] - 0.5)));
        const int ix1 = std::min(g.width_cells - 1, static_cast<int>(std::floor(crossings[k + 1] - 0.5)));
        for (int ix = ix0; ix <= ix1; ++ix) {
          std::uint8_t& cell = mask.at(ix, iy);
          if (!cell) ++set;
          cell = 1;
        }
      }
    }
  }
  return set;
}

}  // namespace anchordb::engine
