#pragma once
// Observation update of a semantic probability layer (thesis 3.4.2, SeAM): a sensor at a pose in the map
// frame with a horizontal field of view and a range saw a cue inside the stimulus polygons.
//  - cells in the stimulus that the sensor could see are raised (log-odds hit),
//  - cells the sensor could see that are not in the stimulus are lowered (log-odds miss),
//  - cells occupied in the base occupancy layer, or behind an occupied cell on the straight line from the
//    sensor, are left unchanged; so is everything outside the field of view or beyond the range.
// "Could see" = the cell centre is within range_m of the sensor, within fov_rad/2 of its heading, and the
// segment from the sensor to the cell centre crosses no occupied cell (unknown cells do not block).
#include <vector>

#include "engine/grid/grid.h"
#include "engine/grid/log_odds.h"

namespace anchordb::engine {

struct Observation {
  Eigen::Vector2d sensor_position_m = Eigen::Vector2d::Zero();  // p_map of the sensor
  double heading_rad = 0.0;                                      // yaw of the sensor's viewing direction in M
  double fov_rad = 1.0;                                          // full horizontal opening angle, (0, 2*pi]
  double range_m = 3.0;                                          // > 0
  std::vector<Polygon2> stimulus_map;                              // where the cue was seen
};

struct ObservationCounts {
  std::size_t raised = 0;
  std::size_t lowered = 0;
  std::size_t unchanged_blocked = 0;        // in view but occupied or occluded
  std::size_t stimulus_outside_view = 0;    // stimulus cells the sensor could not have seen (ignored)
};

// Whether the sensor position lies on a cell of `geometry` (observations from outside the grid are refused).
bool SensorInsideGrid(const GridGeometry& geometry, const Observation& observation);

// Applies the update in place. `occupancy` and `log_odds` must share one geometry (checked: kUnprocessable).
ObservationCounts ApplyObservation(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds,
                                   const LogOddsModel& model, const Observation& observation, LogOddsGrid& log_odds);

// Whether the segment from `from_grid` (continuous grid coordinates, in cells) to the centre of cell
// (ix, iy) crosses an occupied cell other than (ix, iy) and the start cell.
bool IsOccluded(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds, const Eigen::Vector2d& from_grid,
                int ix, int iy);

}  // namespace anchordb::engine
