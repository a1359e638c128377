#pragma once
// Hand-made grids for tests: occupancy from ASCII art, so a test shows its map.
#include <string>
#include <vector>

#include "engine/grid/grid.h"

namespace anchordb::testing {

// Rows are given top (largest iy) first, as drawn: '#' occupied (100), '.' free (0), '?' unknown (-1).
// Resolution 1 m, origin (0, 0, 0) unless given, so cell (ix, iy) has its centre at (ix + 0.5, iy + 0.5).
engine::OccupancyGrid OccupancyFromAscii(const std::vector<std::string>& rows_top_first, double resolution_m = 1.0);

// An empty free grid of w x h cells.
engine::OccupancyGrid FreeGrid(int width, int height, double resolution_m);

}  // namespace anchordb::testing
