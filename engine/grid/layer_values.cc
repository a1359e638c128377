#include "engine/grid/layer_values.h"

#include <algorithm>

namespace anchordb::engine {

ProbabilityGrid OccupancyToProbability(const OccupancyGrid& occupancy) {
  ProbabilityGrid p(occupancy.geometry, 0.5f);
  for (std::size_t i = 0; i < p.cells.size(); ++i) {
    const int v = occupancy.cells[i];
    p.cells[i] = v < 0 ? 0.5f : std::min(100, v) / 100.0f;
  }
  return p;
}

ProbabilityGrid LabelsToProbability(const LabelGrid& labels) {
  ProbabilityGrid p(labels.geometry, 0.0f);
  for (std::size_t i = 0; i < p.cells.size(); ++i) p.cells[i] = labels.cells[i] ? 1.0f : 0.0f;
  return p;
}

ProbabilityGrid MaskToProbability(const MaskGrid& mask) {
  ProbabilityGrid p(mask.geometry, 0.0f);
  for (std::size_t i = 0; i < p.cells.size(); ++i) p.cells[i] = mask.cells[i];
  return p;
}

MaskGrid TrueCells(const ProbabilityGrid& probability) {
  MaskGrid mask(probability.geometry, 0);
  for (std::size_t i = 0; i < mask.cells.size(); ++i) mask.cells[i] = probability.cells[i] > 0.5f ? 1 : 0;
  return mask;
}

OccupancyStatistics CountOccupancy(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds) {
  OccupancyStatistics s;
  for (const std::int8_t v : occupancy.cells) {
    if (IsOccupied(v, thresholds)) ++s.occupied_cells;
    else if (IsFree(v, thresholds)) ++s.free_cells;
    else ++s.unknown_cells;
  }
  return s;
}

LabelStatistics CountLabels(const LabelGrid& labels) {
  LabelStatistics s;
  for (const std::uint16_t v : labels.cells) {
    if (v) ++s.cells_per_label[v];
  }
  return s;
}

ProbabilityStatistics SummariseProbability(const ProbabilityGrid& probability) {
  ProbabilityStatistics s;
  double sum = 0.0;
  for (const float v : probability.cells) {
    sum += v;
    s.min_probability = std::min<double>(s.min_probability, v);
    s.max_probability = std::max<double>(s.max_probability, v);
    s.cells_above_half += v > 0.5f;
  }
  s.mean_probability = probability.cells.empty() ? 0.0 : sum / probability.cells.size();
  return s;
}

}  // namespace anchordb::engine
