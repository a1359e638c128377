#pragma once
// Domain types of the allocentric areal representation (grid layers) and of tracked agents.
// Frames follow REP-103: every map has one allocentric frame M (x forward/east, y left, z up).
// Units are SI throughout: metres, radians, seconds; time stamps are integer nanoseconds since the Unix epoch.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace anchordb {

// A pose in the map frame: position p_map [m] and orientation R_map (unit quaternion).
struct Pose3 {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  // Heading of the frame's x axis projected onto the map's xy plane [rad].
  double YawRad() const;
};

// Geometry of a 2D grid in the map frame. Cell (ix, iy) covers
// [ix, ix+1) x [iy, iy+1) * resolution_m in the grid frame, whose origin is the lower-left corner of cell (0,0)
// and whose pose in the map frame is (origin_x_m, origin_y_m, origin_yaw_rad) -- the map_server `origin`.
// Cell index = iy * width + ix, iy = 0 is the bottom row (ROS OccupancyGrid order, not image order).
struct GridGeometry {
  int width_cells = 0;
  int height_cells = 0;
  double resolution_m = 0.05;
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double origin_yaw_rad = 0.0;

  std::size_t CellCount() const { return static_cast<std::size_t>(width_cells) * height_cells; }
  bool Contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width_cells && iy < height_cells; }
  // Centre of cell (ix, iy) in the map frame [m].
  Eigen::Vector2d CellCenterInMap(int ix, int iy) const;
  // Continuous grid coordinates (in cells) of a map-frame point; floor() gives the cell index.
  Eigen::Vector2d MapToGrid(const Eigen::Vector2d& p_map) const;
  bool operator==(const GridGeometry&) const = default;
};

// How map_server turns grey values into occupancy.
enum class MapMode { kTrinary, kScale, kRaw };
const char* MapModeName(MapMode mode);

// The YAML half of a map_server map, with the values as given.
struct MapServerMeta {
  std::string image;
  double resolution_m = 0.05;
  double origin[3] = {0.0, 0.0, 0.0};  // x [m], y [m], yaw [rad] of the lower-left pixel
  int negate = 0;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapMode mode = MapMode::kTrinary;
  bool mode_given = false;  // whether the YAML had a `mode:` key (export writes it back only then)
};

// OctoMap-style log-odds update parameters, as probabilities.
struct LogOddsParams {
  double hit_probability = 0.7;
  double miss_probability = 0.4;
  double clamp_min_probability = 0.12;
  double clamp_max_probability = 0.97;
};

// Logical operators of fused layers (over layers thresholded to booleans).
enum class FuseOp { kAnd, kOr, kAndNot, kXor };
const char* FuseOpName(FuseOp op);

struct FuseOperand {
  std::string layer;
  double threshold = 0.5;  // probability above which a cell counts as true
};

enum class LayerKind { kOccupancy, kProbability, kFused, kLabel };
const char* LayerKindName(LayerKind kind);

// Pinhole camera intrinsics as in ROS CameraInfo K (no distortion). Pixel (u, v) looks along the optical-frame
// ray ((u - cx) / fx, (v - cy) / fy, 1); u to the right, v down, z forward (REP-103 optical frame).
struct PinholeIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  bool operator==(const PinholeIntrinsics&) const = default;
};

// A tracked person in the map frame.
struct Agent {
  std::string id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;
  Eigen::Vector2d velocity_mps = Eigen::Vector2d::Zero();
  std::int64_t stamp_ns = 0;
};

// A closed polygon in the map frame [m], vertices in order, not repeated at the end.
using Polygon2 = std::vector<Eigen::Vector2d>;

}  // namespace anchordb
