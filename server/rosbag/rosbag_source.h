#pragma once
// Reading a ROS 1 bag for `anchordb import rosbag` (issue 32), behind a header without ROS types: the ROS headers
// (rosbag_storage, roscpp_serialization, tf2) stay inside rosbag_source.cc. The bag is read in passes: tf first (every
// /tf and /tf_static message into one tf2::BufferCore spanning the bag), then the depth and camera info topics are
// checked and each depth image's optical-frame pose in the map frame is looked up at its stamp, then (after the
// caller decided what to store) the depth images are read again, converted to raw little-endian uint16 millimetres.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace anchordb::server {

struct RosbagTopics {
  std::string depth = "/camera/depth/image_rect_raw";  // sensor_msgs/Image, 16UC1 [mm] or 32FC1 [m]
  std::string info = "/camera/depth/camera_info";      // sensor_msgs/CameraInfo
  std::string map_frame = "map";                       // the frame the poses are given in
  std::string grid;  // optional nav_msgs/OccupancyGrid (the last message counts); empty: none
  std::string mask;  // optional sensor_msgs/Image mono8 person mask (nonzero: person); empty: none
  int every = 1;     // use every N-th depth image
};

// The TUM RGB-D benchmark's bag layout: /camera/depth/image 32FC1 metres, /camera/depth/camera_info, /tf, frames
// /world -> ... -> /openni_rgb_optical_frame; the map frame is the benchmark's world frame.
RosbagTopics TumPresetTopics();

// The depth camera's pinhole model from the first CameraInfo (K) [px]. Not schema's PinholeIntrinsics: ROS 1's
// generated messages compile as C++17 only (std::allocator<void>::rebind), schema's headers need C++20.
struct BagCamera {
  int width = 0, height = 0;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
};

// One depth image the scan accepted: its stamp and the pose of its optical frame in the map frame.
struct BagDepthFrame {
  std::int64_t index = 0;  // position among the depth topic's messages (0-based)
  double stamp_s = 0.0;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
};

struct BagScan {
  BagCamera camera;
  std::string encoding;                 // of the first depth image
  std::int64_t depth_messages = 0;      // depth images in the bag
  std::int64_t skipped_every = 0;       // left out by --every
  std::int64_t skipped_no_pose = 0;     // the optical frame's pose could not be looked up at the stamp
  std::int64_t tf_messages = 0;         // /tf and /tf_static messages read
  std::vector<BagDepthFrame> frames;    // accepted, in bag order
  bool has_grid = false;                // the grid topic holds a message
  std::int64_t mask_messages = 0;
};

// Scans the bag (see above). Throws std::invalid_argument with the bag's name for an unreadable or truncated bag, a
// missing depth or info topic, an encoding other than 16UC1 / 32FC1 (or mono16), images of changing size or whose
// data is shorter than their rows, a bag without tf, no depth image whose pose can be looked up, or (with a mask
// topic) a mask that is not mono8 / 8UC1 of the depth images' size.
BagScan ScanBag(const std::string& bag_path, const RosbagTopics& topics);

// A depth image, converted: raw little-endian uint16 millimetres (0: no reading), and the person mask of the same
// stamp as an 8-bit image (0 / 255) when the mask topic has one, else empty.
struct BagDepthPixels {
  std::string depth_mm_le;
  std::vector<std::uint8_t> mask;  // width * height, row-major; empty: none
};

// Reads the depth images whose indices are in `wanted` (ascending) and hands each to `consume` in bag order.
void ReadDepthImages(const std::string& bag_path, const RosbagTopics& topics, const std::vector<std::int64_t>& wanted,
                     const std::function<void(std::int64_t index, const BagDepthPixels& pixels)>& consume);

// The last OccupancyGrid of the grid topic as map_server values: resolution [m], origin, cells (-1 unknown, 0..100).
// Throws std::invalid_argument when its cells do not fill width x height or the resolution is not positive.
struct BagGrid {
  double resolution_m = 0.0;
  double origin_x_m = 0.0, origin_y_m = 0.0;  // the lower-left cell's corner in the map frame
  double origin_yaw_rad = 0.0;
  int width = 0, height = 0;
  std::vector<std::int8_t> cells;  // row-major from the origin
};
BagGrid ReadLastGrid(const std::string& bag_path, const std::string& grid_topic);

}  // namespace anchordb::server
