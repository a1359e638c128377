#pragma once
// A dense 2D grid of cells over a map-frame area. Pure std/Eigen: no OpenCV, SQLite or HTTP here.
#include <cstdint>
#include <vector>

#include "schema/types.h"

namespace anchordb::engine {

template <typename T>
struct Grid {
  GridGeometry geometry;
  std::vector<T> cells;  // index = iy * width + ix, iy = 0 is the bottom row

  Grid() = default;
  Grid(const GridGeometry& g, T fill) : geometry(g), cells(g.CellCount(), fill) {}
  T& at(int ix, int iy) { return cells[static_cast<std::size_t>(iy) * geometry.width_cells + ix]; }
  const T& at(int ix, int iy) const { return cells[static_cast<std::size_t>(iy) * geometry.width_cells + ix]; }
};

// Occupancy in ROS OccupancyGrid values: -1 unknown, 0 free ... 100 occupied.
using OccupancyGrid = Grid<std::int8_t>;
// Log-odds of a semantic cue per cell (0 = p 0.5, unknown).
using LogOddsGrid = Grid<float>;
// Probabilities in [0, 1] per cell (what readers of any layer kind see).
using ProbabilityGrid = Grid<float>;
// Booleans as 0/1 bytes.
using MaskGrid = Grid<std::uint8_t>;
// Label ids per cell; 0 = no label.
using LabelGrid = Grid<std::uint16_t>;

// Which occupancy values count as obstacle / free space for ray casting and path search.
struct OccupancyThresholds {
  int occupied_min = 65;  // value >= this blocks sight and motion
  int free_max = 25;      // 0 <= value <= this is known free space
};

inline bool IsOccupied(std::int8_t v, const OccupancyThresholds& t) { return v >= t.occupied_min; }
inline bool IsFree(std::int8_t v, const OccupancyThresholds& t) { return v >= 0 && v <= t.free_max; }

}  // namespace anchordb::engine
