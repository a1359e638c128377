#pragma once
// Rasterisation of map-frame polygons onto a grid: a cell belongs to a polygon when its centre lies inside or on
// its edge (even-odd rule), so results do not depend on how a polygon's edges graze cell borders.
#include <vector>

#include "engine/grid/grid.h"

namespace anchordb::engine {

// Marks (sets to 1) the cells of `mask` whose centres lie inside any polygon. Returns how many cells were set.
std::size_t RasterisePolygons(const std::vector<Polygon2>& polygons_map, MaskGrid& mask);

}  // namespace anchordb::engine
