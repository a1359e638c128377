#pragma once
// Observation viewpoints around a surface (thesis 3.4.3): binarise the surface, dilate by ~1 m, keep the
// boundary of the dilated area (Sobel), drop cells that are not known free, too near an obstacle, unreachable
// from the robot (path search on the occupancy layer) or outside the wanted distance from the surface, cluster
// the rest with k-means and rate each cluster's representative cell by travel distance and by its position
// relative to the person (beside best, in front medium, behind worst).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/grid/attention.h"
#include "engine/grid/grid.h"
#include "engine/grid/regions.h"

namespace anchordb::engine {

struct ViewpointOptions {
  double dilation_radius_m = 1.0;        // structuring element radius around the surface
  double min_obstacle_distance_m = 0.35; // clearance a viewpoint keeps from occupied cells
  double robot_radius_m = 0.25;          // clearance of cells the robot may drive through
  double min_surface_distance_m = 0.5;
  double max_surface_distance_m = 2.0;
  double min_person_distance_m = 0.5;    // do not stand on the person's toes
  double cluster_spacing_m = 0.75;       // k = boundary length / spacing
  double travel_scale_m = 10.0;          // travel score = 1 / (1 + travel / scale)
  double weight_position = 0.7;          // score = w_pos * position + w_travel * travel
  double weight_travel = 0.3;
  int max_viewpoints = 12;
  std::uint64_t seed = 42;               // k-means initialisation (deterministic)
  OccupancyThresholds occupancy;
};

struct Viewpoint {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;               // facing the surface centroid
  double score = 0.0;
  double position_score = 0.0;        // beside 0.75-1, in front 0.4-0.7, behind 0-0.3 (see PositionScore)
  double travel_score = 0.0;
  double travel_distance_m = 0.0;     // shortest 8-connected path from the robot
  double surface_distance_m = 0.0;    // to the nearest surface cell centre
  double person_distance_m = 0.0;
  double relative_angle_rad = 0.0;    // between the person's heading and the direction person -> viewpoint
  std::string relation;               // "beside", "in_front", "behind"
};

struct ViewpointPlan {
  std::vector<Viewpoint> viewpoints;  // best first
  std::size_t boundary_cells = 0;
  std::size_t candidate_cells = 0;    // boundary cells left after the filters
  int clusters = 0;
};

// `surface` marks the surface cells (same geometry as `occupancy`). The robot must stand on a known free cell
// (kUnprocessable otherwise).
ViewpointPlan PlanViewpoints(const OccupancyGrid& occupancy, const MaskGrid& surface, const Eigen::Vector2d& robot_m,
                             const Agent& person, const ViewpointOptions& options);

// Which of `regions` (ExtractRegions order, ids 1..n; none is kUnprocessable) viewpoints go around: `requested_id`
// when given (Error kNotFound, field "region", when no region has that id), else the region the person attends to
// (ComputeAttention with `attention`), else the region nearest to the person. Returns its id.
int ChooseSurfaceRegion(const std::vector<Region>& regions, const GridGeometry& geometry, const Agent& person,
                        const AttentionOptions& attention, std::optional<int> requested_id);

// Shortest 8-connected path lengths [m] from `start` over cells that are free and keep `clearance_m` from
// obstacles (diagonal steps only between two passable side neighbours); unreachable cells are +inf. The start
// cell itself is always traversable.
std::vector<double> TravelDistances(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds, int start_ix,
                                    int start_iy, double clearance_m);

// Position score of a viewpoint at angle `relative_angle_rad` in [0, pi] from the person's heading; ordered by
// the relation classes (in front < 45 deg, beside 45-135 deg, behind > 135 deg): beside best, behind worst.
double PositionScore(double relative_angle_rad);

}  // namespace anchordb::engine
