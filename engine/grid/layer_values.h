#pragma once
// What the cells of each layer kind mean when read as per-cell probabilities (the view regions, attention,
// viewpoints, fused layers and image exports take of any layer), and the statistics a layer reports.
#include <cstddef>
#include <map>

#include "engine/grid/grid.h"

namespace anchordb::engine {

// Occupancy value v in 0..100 as p = v / 100 (values above 100 count as 100); unknown (-1) as 0.5.
ProbabilityGrid OccupancyToProbability(const OccupancyGrid& occupancy);
// 1 where a cell carries any label, 0 elsewhere.
ProbabilityGrid LabelsToProbability(const LabelGrid& labels);
// A boolean mask (0/1 bytes) as probabilities 0 and 1.
ProbabilityGrid MaskToProbability(const MaskGrid& mask);

// The boolean reading of any layer: cells with p strictly above 0.5 (what a raw export of a layer read as
// probabilities carries; never-observed cells at 0.5 are false).
MaskGrid TrueCells(const ProbabilityGrid& probability);

// Occupancy cells by map_server class (OccupancyThresholds, grid.h): occupied, known free, and the rest.
struct OccupancyStatistics {
  std::size_t occupied_cells = 0;
  std::size_t free_cells = 0;
  std::size_t unknown_cells = 0;  // -1, and the values between free_max and occupied_min
};
OccupancyStatistics CountOccupancy(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds);

struct LabelStatistics {
  std::map<int, std::size_t> cells_per_label;  // label id -> cells; ids without cells are absent
};
LabelStatistics CountLabels(const LabelGrid& labels);

struct ProbabilityStatistics {
  double min_probability = 1.0;  // 1 (and max 0) for a grid without cells
  double max_probability = 0.0;
  double mean_probability = 0.0;
  std::size_t cells_above_half = 0;  // cells with p strictly above 0.5
};
ProbabilityStatistics SummariseProbability(const ProbabilityGrid& probability);

}  // namespace anchordb::engine
