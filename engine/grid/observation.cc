#include "engine/grid/observation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/grid/raster.h"
#include "engine/grid/visibility.h"
#include "schema/error.h"

namespace anchordb::engine {

bool IsOccluded(const OccupancyGrid& occupancy, const OccupancyThresholds& t, const Eigen::Vector2d& from, int tx,
                int ty) {
  // Amanatides-Woo traversal of the cells the segment passes through.
  const double x1 = tx + 0.5, y1 = ty + 0.5;
  const double dx = x1 - from.x(), dy = y1 - from.y();
  int ix = static_cast<int>(std::floor(from.x())), iy = static_cast<int>(std::floor(from.y()));
  const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_x = dx != 0 ? std::abs(1.0 / dx) : inf;
  const double t_delta_y = dy != 0 ? std::abs(1.0 / dy) : inf;
  double t_max_x = dx != 0 ? ((step_x > 0 ? (ix + 1 - from.x()) : (from.x() - ix)) * t_delta_x) : inf;
  double t_max_y = dy != 0 ? ((step_y > 0 ? (iy + 1 - from.y()) : (from.y() - iy)) * t_delta_y) : inf;
  const GridGeometry& g = occupancy.geometry;
  // Bounded by the Manhattan distance; the start cell is not checked (the sensor stands there).
  const int max_steps = std::abs(tx - ix) + std::abs(ty - iy);
  for (int s = 0; s < max_steps; ++s) {
    if (t_max_x < t_max_y) {
      ix += step_x;
      t_max_x += t_delta_x;
    } else {
      iy += step_y;
      t_max_y += t_delta_y;
    }
    if (ix == tx && iy == ty) return false;
    if (g.Contains(ix, iy) && IsOccupied(occupancy.at(ix, iy), t)) return true;
  }
  return false;
}

ObservationCounts ApplyObservation(const OccupancyGrid& occupancy, const OccupancyThresholds& t,
                                   const LogOddsModel& model, const Observation& obs, LogOddsGrid& log_odds) {
  const GridGeometry& g = log_odds.geometry;
  if (!(occupancy.geometry == g)) {
    throw Error(ErrorCode::kUnprocessable, "probability layer and its base layer have different grids");
  }
  const Eigen::Vector2d sensor_grid = g.MapToGrid(obs.sensor_position_m);
  const double range_cells = obs.range_m / g.resolution_m;
  const int ix0 = std::max(0, static_cast<int>(std::floor(sensor_grid.x() - range_cells)));
  const int ix1 = std::min(g.width_cells - 1, static_cast<int>(std::ceil(sensor_grid.x() + range_cells)));
  const int iy0 = std::max(0, static_cast<int>(std::floor(sensor_grid.y() - range_cells)));
  const int iy1 = std::min(g.height_cells - 1, static_cast<int>(std::ceil(sensor_grid.y() + range_cells)));

  MaskGrid stimulus(g, 0);
  const std::size_t stimulus_cells = RasterisePolygons(obs.stimulus_map, stimulus);

  const double half_fov = obs.fov_rad / 2.0;
  const bool full_circle = obs.fov_rad >= 2.0 * std::numbers::pi - 1e-9;
  // The heading in grid coordinates (the grid may be rotated in the map frame).
  const double heading_grid = obs.heading_rad - g.origin_yaw_rad;
  const double range_sq = range_cells * range_cells;
  // Same answers as IsOccluded per cell, without a traversal per cell (see visibility.h).
  OcclusionIndex occlusion(occupancy, t, sensor_grid, range_cells);
  const int occupied_min = t.occupied_min;
  std::size_t raised = 0, lowered = 0, blocked = 0;
  for (int iy = iy0; iy <= iy1; ++iy) {
    const std::size_t row = static_cast<std::size_t>(iy) * g.width_cells;
    const std::int8_t* const occupancy_row = occupancy.cells.data() + row;
    const std::uint8_t* const stimulus_row = stimulus.cells.data() + row;
    float* const log_odds_row = log_odds.cells.data() + row;
    for (int ix = ix0; ix <= ix1; ++ix) {
      const double dx = ix + 0.5 - sensor_grid.x(), dy = iy + 0.5 - sensor_grid.y();
      if (dx * dx + dy * dy > range_sq) continue;
      if (!full_circle && (dx != 0 || dy != 0)) {
        const double angle = std::remainder(std::atan2(dy, dx) - heading_grid, 2.0 * std::numbers::pi);
        if (std::abs(angle) > half_fov) continue;
      }
      if (occupancy_row[ix] >= occupied_min || occlusion.IsOccluded(ix, iy)) {
        ++blocked;
        continue;
      }
      float& l = log_odds_row[ix];
      if (stimulus_row[ix]) {
        l = model.Raise(l);
        ++raised;
      } else {
        l = model.Lower(l);
        ++lowered;
      }
    }
  }
  ObservationCounts counts;
  counts.raised = raised;
  counts.lowered = lowered;
  counts.unchanged_blocked = blocked;
  // Every raised cell is a stimulus cell the sensor saw.
  counts.stimulus_outside_view = stimulus_cells - raised;
  return counts;
}

bool SensorInsideGrid(const GridGeometry& geometry, const Observation& observation) {
  const Eigen::Vector2d sensor_grid = geometry.MapToGrid(observation.sensor_position_m);
  return geometry.Contains(static_cast<int>(std::floor(sensor_grid.x())), static_cast<int>(std::floor(sensor_grid.y())));
}

}  // namespace anchordb::engine
