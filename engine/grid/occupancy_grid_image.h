#pragma once
// A ROS nav_msgs/OccupancyGrid as a map_server pair (issue 32): the rosbag importer (server/rosbag) and the anchordb_ros
// bridge node (clients/ros) import a robot's map as an occupancy layer through this one conversion, so both give the
// same layer. Header-only, C++17 and std types only: the bridge compiles as C++17 (ROS 1's generated messages).
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace anchordb::engine {

// Grey of one OccupancyGrid cell in map_server's trinary reading of the YAML below: -1 (unknown) -> 205,
// >= 65 (occupied_thresh 0.65) -> 0, <= 19 (below free_thresh 0.196) -> 254, anything between -> 205 (unknown).
inline std::uint8_t OccupancyGridGrey(int cell) {
  if (cell < 0) return 205;
  if (cell >= 65) return 0;
  if (cell <= 19) return 254;
  return 205;
}

// The image rows of a grid whose `cells` (width x height, row-major from the origin: row 0 is the smallest y) are
// flipped so that the image's top row is the largest y, as map_server files are. Returns width * height grey bytes;
// empty when cells.size() != width * height.
inline std::vector<std::uint8_t> OccupancyGridImage(const std::vector<std::int8_t>& cells, int width, int height) {
  if (width <= 0 || height <= 0 || cells.size() != static_cast<std::size_t>(width) * height) return {};
  std::vector<std::uint8_t> out(cells.size());
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      out[static_cast<std::size_t>(height - 1 - r) * width + c] = OccupancyGridGrey(cells[static_cast<std::size_t>(r) * width + c]);
    }
  }
  return out;
}

// The map_server YAML of that image: resolution [m/cell], the origin (x, y [m], yaw [rad]) of the grid's lower-left
// cell in the map frame, trinary mode, the thresholds OccupancyGridGrey assumes.
inline std::string OccupancyGridYaml(const std::string& image_name, double resolution_m, double origin_x_m,
                                     double origin_y_m, double origin_yaw_rad) {
  char numbers[256];
  std::snprintf(numbers, sizeof(numbers),
                "resolution: %.9g\norigin: [%.9g, %.9g, %.9g]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
                resolution_m, origin_x_m, origin_y_m, origin_yaw_rad);
  return "image: " + image_name + "\n" + numbers;
}

}  // namespace anchordb::engine
