#include "services/grid/grid_settings.h"

namespace anchordb::services {

void BindGridSettings(SettingsBinder& b, ServiceLimits& limits, GridDefaults& grid) {
  b.Bind("max_map_pixels", "largest accepted map image [pixels]", &limits.max_map_pixels, 1, 4e8);
  b.Bind("max_polygons", "most polygons in one request", &limits.max_polygons, 1, 1e6);
  b.Bind("max_polygon_vertices", "most vertices in one polygon", &limits.max_polygon_vertices, 3, 1e7);
  b.Bind("max_list_limit", "largest page size of list routes", &limits.max_list_limit, 1, 1e6);
  b.Bind("occupied_min", "occupancy value (0-100) from which a cell blocks sight and motion", &grid.occupancy.occupied_min, 1, 100);
  b.Bind("free_max", "occupancy value (0-100) up to which a cell is known free", &grid.occupancy.free_max, 0, 99);
  b.Require([&grid] { return grid.occupancy.free_max < grid.occupancy.occupied_min; }, "free_max must be below occupied_min");
  b.Bind("attention_near_m", "distance person-surface that counts as next to it [m]", &grid.attention.near_distance_m, 0, 100);
  b.Bind("attention_max_facing_rad", "largest angle between heading and surface that counts as facing it [rad]",
         &grid.attention.max_facing_angle_rad, 0, 3.1416);
  auto& v = grid.viewpoints;
  b.Bind("viewpoint_dilation_m", "radius of the dilation around the surface (thesis: ~1 m) [m]", &v.dilation_radius_m, 0.05, 10);
  b.Bind("viewpoint_min_obstacle_m", "clearance a viewpoint keeps from obstacles [m]", &v.min_obstacle_distance_m, 0, 10);
  b.Bind("viewpoint_robot_radius_m", "clearance of the path the robot drives [m]", &v.robot_radius_m, 0, 5);
  b.Bind("viewpoint_min_surface_m", "nearest a viewpoint may be to the surface [m]", &v.min_surface_distance_m, 0, 10);
  b.Bind("viewpoint_max_surface_m", "farthest a viewpoint may be from the surface [m]", &v.max_surface_distance_m, 0, 20);
  b.Require([&v] { return v.min_surface_distance_m <= v.max_surface_distance_m; },
            "viewpoint_min_surface_m exceeds viewpoint_max_surface_m");
  b.Bind("viewpoint_min_person_m", "nearest a viewpoint may be to the person [m]", &v.min_person_distance_m, 0, 10);
  b.Bind("viewpoint_spacing_m", "boundary length per k-means cluster [m]", &v.cluster_spacing_m, 0.05, 100);
  b.Bind("viewpoint_travel_scale_m", "travel distance at which the travel score halves [m]", &v.travel_scale_m, 0.01, 1e4);
  b.Bind("viewpoint_weight_position", "weight of the position-relative-to-person score", &v.weight_position, 0, 1);
  b.Bind("viewpoint_weight_travel", "weight of the travel score", &v.weight_travel, 0, 1);
  b.Bind("viewpoint_seed", "seed of the k-means initialisation", &v.seed, 0, 9.0e15);
}

}  // namespace anchordb::services
