#pragma once
// Regions of a layer (thesis 3.4.2): threshold, then region growing (8-connected components), then the outer
// contour of each region as a polygon in the map frame.
#include <vector>

#include "engine/grid/grid.h"

namespace anchordb::engine {

struct Region {
  int id = 0;                       // 1-based, in order of decreasing area
  std::size_t cell_count = 0;
  double area_m2 = 0.0;             // cell_count * resolution^2
  Eigen::Vector2d centroid_m = Eigen::Vector2d::Zero();  // mean of the cell centres, map frame
  Polygon2 polygon_m;               // outer boundary through the centres of the boundary cells
  double mean_probability = 0.0;
  std::vector<int> cells;           // cell indices (iy * width + ix)
};

// Regions of cells with probability strictly above threshold whose area is at least min_area_m2, largest first.
// (Strict, so a never-observed layer, all 0.5, has no region at the default threshold 0.5.)
std::vector<Region> ExtractRegions(const ProbabilityGrid& probability, double threshold, double min_area_m2);

// The cells of `region` (extracted from a grid of `geometry`) set to 1, the rest 0.
MaskGrid RegionMask(const Region& region, const GridGeometry& geometry);

}  // namespace anchordb::engine
