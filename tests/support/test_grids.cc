#include "tests/support/test_grids.h"

namespace anchordb::testing {

engine::OccupancyGrid OccupancyFromAscii(const std::vector<std::string>& rows, double resolution_m) {
  GridGeometry g;
  g.width_cells = static_cast<int>(rows.front().size());
  g.height_cells = static_cast<int>(rows.size());
  g.resolution_m = resolution_m;
  engine::OccupancyGrid grid(g, 0);
  for (int r = 0; r < g.height_cells; ++r) {
    const int iy = g.height_cells - 1 - r;
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const char c = rows[r][ix];
      grid.at(ix, iy) = c == '#' ? 100 : c == '?' ? -1 : 0;
    }
  }
  return grid;
}

engine::OccupancyGrid FreeGrid(int width, int height, double resolution_m) {
  GridGeometry g;
  g.width_cells = width;
  g.height_cells = height;
  g.resolution_m = resolution_m;
  return engine::OccupancyGrid(g, 0);
}

}  // namespace anchordb::testing
