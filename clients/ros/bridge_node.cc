// anchordb_ros: subscriptions and the frames' way to the server (bridge_node.h).
#include "clients/ros/bridge_node.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <anchordb_ros/ChangeEvent.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include "engine/grid/occupancy_grid_image.h"
#include "engine/image/png_codec.h"

namespace anchordb::ros_bridge {
namespace {

// Whether the image's rows of `bytes_per_pixel` fit its data (a wrong step or short data would be read past its end).
bool RowsFit(const sensor_msgs::Image& image, std::size_t bytes_per_pixel) {
  return image.step >= image.width * bytes_per_pixel && image.data.size() >= static_cast<std::size_t>(image.step) * image.height;
}

// A depth encoding we read (16UC1 / mono16 mm, 32FC1 m) whose rows fit the data.
bool DepthReadable(const sensor_msgs::Image& image) {
  const bool metres = image.encoding == "32FC1";
  if (!metres && image.encoding != "16UC1" && image.encoding != "mono16") return false;
  return RowsFit(image, metres ? 4 : 2);
}

// Row-major uint16 millimetres (0: no reading) of a DepthReadable image.
std::vector<std::uint16_t> Millimetres(const sensor_msgs::Image& image) {
  const bool metres = image.encoding == "32FC1";
  std::vector<std::uint16_t> out(static_cast<std::size_t>(image.width) * image.height, 0);
  for (std::size_t r = 0; r < image.height; ++r) {
    const std::uint8_t* row = image.data.data() + r * image.step;
    for (std::size_t c = 0; c < image.width; ++c) {
      std::uint16_t& mm = out[r * image.width + c];
      if (metres) {
        float m = 0;
        std::memcpy(&m, row + c * 4, 4);
        if (std::isfinite(m) && m > 0.0f) mm = static_cast<std::uint16_t>(std::min(65535.0f, std::round(m * 1000.0f)));
      } else {
        const std::uint8_t* b = row + c * 2;
        mm = image.is_bigendian ? static_cast<std::uint16_t>(b[0] << 8 | b[1]) : static_cast<std::uint16_t>(b[1] << 8 | b[0]);
      }
    }
  }
  return out;
}

// The mask (mono8 / 8UC1, checked by OnMask) as an 8-bit PNG, 255 where it is nonzero.
std::string MaskPng(const sensor_msgs::Image& mask) {
  engine::PngImage png;
  png.width = static_cast<int>(mask.width), png.height = static_cast<int>(mask.height), png.channels = 1, png.bit_depth = 8;
  png.bytes.resize(static_cast<std::size_t>(mask.width) * mask.height);
  for (std::size_t r = 0; r < mask.height; ++r) {
    for (std::size_t c = 0; c < mask.width; ++c) png.bytes[r * mask.width + c] = mask.data[r * mask.step + c] ? 255 : 0;
  }
  return engine::EncodePngImage(png);
}

Eigen::Isometry3d IsometryOf(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return X;
}


}  // namespace

NodeParams LoadParams(const ros::NodeHandle& pnh) {
  NodeParams p;
  pnh.param("server_host", p.host, p.host);
  pnh.param("server_port", p.port, p.port);
  pnh.param("token", p.token, p.token);
  pnh.param("map", p.map, p.map);
  pnh.param("map_frame", p.map_frame, p.map_frame);
  pnh.param("timeout_s", p.timeout_s, p.timeout_s);
  pnh.param("poll_period_s", p.poll_period_s, p.poll_period_s);
  pnh.param("create_map", p.create_map, p.create_map);
  pnh.param("publish_past_events", p.publish_past_events, p.publish_past_events);
  pnh.param("merge", p.session.merge, p.session.merge);
  pnh.param("initial_backoff_s", p.session.initial_backoff_s, p.session.initial_backoff_s);
  pnh.param("max_backoff_s", p.session.max_backoff_s, p.session.max_backoff_s);
  engine::ObservationRuleParams& r = p.session.rule;
  pnh.param("still_window_s", r.still_window_s, r.still_window_s);
  pnh.param("still_translation_m", r.still_translation_m, r.still_translation_m);
  pnh.param("still_rotation_rad", r.still_rotation_rad, r.still_rotation_rad);
  pnh.param("min_dwell_s", r.min_dwell_s, r.min_dwell_s);
  pnh.param("leave_translation_m", r.leave_translation_m, r.leave_translation_m);
  pnh.param("leave_rotation_rad", r.leave_rotation_rad, r.leave_rotation_rad);
  pnh.param("max_gap_s", r.max_gap_s, r.max_gap_s);
  pnh.param("mask_topic", p.mask_topic, p.mask_topic);
  pnh.param("mask_wait_s", p.mask_wait_s, p.mask_wait_s);
  pnh.param("grid_topic", p.grid_topic, p.grid_topic);
  pnh.param("grid_layer", p.grid_layer, p.grid_layer);
  std::string layers;
  pnh.param("layers", layers, layers);
  for (std::size_t start = 0; start < layers.size();) {
    const std::size_t comma = std::min(layers.find(',', start), layers.size());
    if (comma > start) p.layers.push_back(layers.substr(start, comma - start));
    start = comma + 1;
  }
  p.session.map = p.map;
  return p;
}

BridgeNode::BridgeNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& p)
    : p_(p),
      frames_client_(p.host, p.port, p.token, p.timeout_s),
      query_client_(p.host, p.port, p.token, p.timeout_s),
      session_(frames_client_, p.session),
      listener_(tf_, nh, false),  // tf on the spin thread, see bridge_node.h
      depth_sub_(nh, "depth/image", 30),
      depth_filter_(depth_sub_, tf_, p.map_frame, 30, nh) {
  depth_filter_.registerCallback(&BridgeNode::OnDepth, this);
  depth_filter_.registerFailureCallback([this](const sensor_msgs::Image::ConstPtr&, tf2_ros::FilterFailureReason) {
    ++tf_drops_;
  });
  info_sub_ = nh.subscribe("depth/camera_info", 5, &BridgeNode::OnInfo, this);
  if (!p.mask_topic.empty()) mask_sub_ = nh.subscribe(p.mask_topic, 30, &BridgeNode::OnMask, this);
  if (!p.grid_topic.empty()) grid_sub_ = nh.subscribe(p.grid_topic, 1, &BridgeNode::OnGrid, this);
  events_pub_ = pnh.advertise<anchordb_ros::ChangeEvent>("events", 100);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("instances", 1, true);
  status_pub_ = pnh.advertise<std_msgs::String>("status", 1, true);
  for (const std::string& layer : p.layers) {
    layer_pubs_[layer] = pnh.advertise<nav_msgs::OccupancyGrid>("layers/" + layer, 1, true);
  }
  where_srv_ = pnh.advertiseService("where_is", &BridgeNode::WhereIs, this);
  label_srv_ = pnh.advertiseService("label", &BridgeNode::Label, this);
  poll_timer_ = nh.createTimer(ros::Duration(p.poll_period_s), &BridgeNode::Poll, this);
  try {
    PrimeEvents();
  } catch (const client::ApiError& e) {
    events_primed_ = e.status() == 404;  // no map yet, so no past event: every event of the map will be new
  } catch (const std::exception&) {     // the server is away: the first poll that reaches it primes
  }
  ROS_INFO("anchordb_ros: server %s:%d, map '%s' in frame '%s'%s%s", p.host.c_str(), p.port, p.map.c_str(),
           p.map_frame.c_str(), p.mask_topic.empty() ? "" : (", person mask " + p.mask_topic).c_str(),
           p.grid_topic.empty() ? "" : (", map " + p.grid_topic + " -> layer " + p.grid_layer).c_str());
}

std::string BridgeNode::Finish() {
  DrainPending(true);
  session_.Finish();
  const SessionCounts& c = session_.counts();
  char line[480];
  std::snprintf(line, sizeof(line), "anchordb_ros: offered %ld, stored %ld (acknowledged), skipped %ld, dropped %ld, "
                "no tf %ld, scenes opened %ld closed %ld, server failures %ld, masked %ld (dynamic pixels %ld), "
                "without mask %ld, masks refused %ld, grid imported %s", static_cast<long>(c.offered),
                static_cast<long>(c.stored), static_cast<long>(c.skipped_moving), static_cast<long>(c.dropped),
                static_cast<long>(tf_drops_), static_cast<long>(c.scenes_opened), static_cast<long>(c.scenes_closed),
                static_cast<long>(c.server_failures), static_cast<long>(c.frames_masked),
                static_cast<long>(c.dynamic_pixels), static_cast<long>(without_mask_), static_cast<long>(masks_refused_),
                grid_done_ ? "yes" : "no");
  return line;
}

void BridgeNode::OnInfo(const sensor_msgs::CameraInfo::ConstPtr& info) {
  if (info->K[0] <= 0 || info->K[4] <= 0 || info->width == 0 || info->height == 0) return;
  client::Camera c;
  c.width = static_cast<int>(info->width), c.height = static_cast<int>(info->height);
  c.fx = info->K[0], c.fy = info->K[4], c.cx = info->K[2], c.cy = info->K[5];
  camera_ = c;
}

void BridgeNode::OnDepth(const sensor_msgs::Image::ConstPtr& image) {
  if (!camera_ || static_cast<int>(image->width) != camera_->width || static_cast<int>(image->height) != camera_->height) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: depth image without a matching camera info; skipped");
    return;
  }
  if (!DepthReadable(*image)) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: depth encoding '%s' not supported (16UC1, mono16, 32FC1) or rows longer than "
                      "the data", image->encoding.c_str());
    return;
  }
  if (!map_ready_ && !EnsureMap()) return;
  geometry_msgs::TransformStamped X;
  try {  // the message filter let the image through once this transform could be looked up
    X = tf_.lookupTransform(p_.map_frame, image->header.frame_id, image->header.stamp);
  } catch (const tf2::TransformException&) {
    ++tf_drops_;
    return;
  }
  if (p_.mask_topic.empty()) {
    Store(*image, IsometryOf(X.transform), nullptr);
    return;
  }
  pending_.push_back({image, IsometryOf(X.transform), ros::WallTime::now().toSec()});
  DrainPending(false);
}

void BridgeNode::OnMask(const sensor_msgs::Image::ConstPtr& mask) {
  const bool eight_bit = mask->encoding == "mono8" || mask->encoding == "8UC1";
  if (!eight_bit || !RowsFit(*mask, 1) ||
      (camera_ && (static_cast<int>(mask->width) != camera_->width || static_cast<int>(mask->height) != camera_->height))) {
    ++masks_refused_;
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: person mask '%s' %u x %u refused (mono8 / 8UC1 of the depth images' size)",
                      mask->encoding.c_str(), mask->width, mask->height);
    return;
  }
  masks_[mask->header.stamp.toNSec()] = mask;
  while (masks_.size() > 64) masks_.erase(masks_.begin());  // masks whose depth image never came
  DrainPending(false);
}

void BridgeNode::DrainPending(bool all) {
  const double now_s = ros::WallTime::now().toSec();
  while (!pending_.empty()) {
    const PendingDepth& head = pending_.front();
    const auto mask = masks_.find(head.image->header.stamp.toNSec());
    if (mask != masks_.end()) {
      Store(*head.image, head.X_MapCamera, mask->second.get());
      masks_.erase(masks_.begin(), std::next(mask));  // the masks of this stamp and older are no longer needed
    } else if (all || now_s - head.arrived_wall_s >= p_.mask_wait_s || pending_.size() > 64) {
      ++without_mask_;
      ROS_WARN_THROTTLE(5.0, "anchordb_ros: no person mask on %s for the depth image of %.3f s; stored without one",
                        p_.mask_topic.c_str(), head.image->header.stamp.toSec());
      Store(*head.image, head.X_MapCamera, nullptr);
    } else {
      return;
    }
    pending_.pop_front();
  }
}

void BridgeNode::Store(const sensor_msgs::Image& image, const Eigen::Isometry3d& X_MapCamera,
                       const sensor_msgs::Image* mask) {
  if (!camera_ || static_cast<int>(image.width) != camera_->width || static_cast<int>(image.height) != camera_->height) {
    return;  // the camera info changed while the image waited for its mask
  }
  if (mask && (mask->width != image.width || mask->height != image.height)) {  // came before the first camera info
    ++masks_refused_;
    mask = nullptr;
  }
  const std::vector<std::uint16_t> depth = Millimetres(image);
  const FrameOutcome outcome = session_.OnFrame(image.header.stamp.toSec(), X_MapCamera, *camera_, depth,
                                                mask ? MaskPng(*mask) : std::string(), ros::WallTime::now().toSec());
  if (outcome == FrameOutcome::kDropped) {
    ROS_WARN_THROTTLE(2.0, "anchordb_ros: frame not stored (%s); retrying in %.1f s", session_.last_error().c_str(),
                      session_.backoff_s());
  }
}

void BridgeNode::OnGrid(const nav_msgs::OccupancyGrid::ConstPtr& grid) {
  if (grid_done_) {
    ROS_INFO_THROTTLE(60.0, "anchordb_ros: layer '%s' was imported from the first map; a later map does not replace it",
                      p_.grid_layer.c_str());
    return;
  }
  if (grid->data.empty() || grid->data.size() != static_cast<std::size_t>(grid->info.width) * grid->info.height ||
      !(grid->info.resolution > 0.0f)) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: map on %s refused: %zu cells for %u x %u at resolution %g", p_.grid_topic.c_str(),
                      grid->data.size(), grid->info.width, grid->info.height, grid->info.resolution);
    return;
  }
  grid_ = grid;
  ImportGrid();
}

// The received map as the occupancy layer (the conversion of `anchordb import rosbag`, engine/grid/occupancy_grid_image.h).
// A server that is down or answers 5xx: retried at the next poll. The layer existing already (409): left as it is.
void BridgeNode::ImportGrid() {
  if (!grid_ || (!map_ready_ && !EnsureMap())) return;
  const nav_msgs::OccupancyGrid& g = *grid_;
  engine::PngImage image;
  image.width = static_cast<int>(g.info.width), image.height = static_cast<int>(g.info.height);
  image.channels = 1, image.bit_depth = 8;
  image.bytes = engine::OccupancyGridImage(g.data, image.width, image.height);
  const geometry_msgs::Quaternion& q = g.info.origin.orientation;
  const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  const std::string yaml = engine::OccupancyGridYaml("grid.png", g.info.resolution, g.info.origin.position.x,
                                                     g.info.origin.position.y, yaw);
  try {
    query_client_.ImportLayer(p_.map, p_.grid_layer, yaml, engine::EncodePngImage(image));
    ROS_INFO("anchordb_ros: map %u x %u imported as layer '%s'", g.info.width, g.info.height, p_.grid_layer.c_str());
    grid_done_ = true;
    grid_.reset();
  } catch (const client::ApiError& e) {
    if (e.status() >= 500) {
      ROS_WARN_THROTTLE(5.0, "anchordb_ros: importing the map: %s; retrying", e.what());
      return;
    }
    ROS_WARN("anchordb_ros: map not imported as layer '%s': %s", p_.grid_layer.c_str(), e.what());
    grid_done_ = e.status() == 409;  // the layer is there already: layers are not replaced
    grid_.reset();
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: importing the map: %s; retrying", e.what());
  }
}

}  // namespace anchordb::ros_bridge
