// anchordb_ros: subscriptions and the frames' way to the server (bridge_node.h).
#include "clients/ros/bridge_node.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <anchordb_ros/ChangeEvent.h>
#include <nav_msgs/OccupancyGrid.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

namespace anchordb::ros_bridge {
namespace {

// Row-major uint16 millimetres (0: no reading); empty for an encoding other than 16UC1 / mono16 / 32FC1.
std::vector<std::uint16_t> Millimetres(const sensor_msgs::Image& image) {
  const bool metres = image.encoding == "32FC1";
  if (!metres && image.encoding != "16UC1" && image.encoding != "mono16") return {};
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
      listener_(tf_),
      depth_sub_(nh, "depth/image", 30),
      depth_filter_(depth_sub_, tf_, p.map_frame, 30, nh) {
  depth_filter_.registerCallback(&BridgeNode::OnDepth, this);
  depth_filter_.registerFailureCallback([this](const sensor_msgs::Image::ConstPtr&, tf2_ros::FilterFailureReason) {
    ++tf_drops_;
  });
  info_sub_ = nh.subscribe("depth/camera_info", 5, &BridgeNode::OnInfo, this);
  events_pub_ = pnh.advertise<anchordb_ros::ChangeEvent>("events", 100);
  markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("instances", 1, true);
  status_pub_ = pnh.advertise<std_msgs::String>("status", 1, true);
  for (const std::string& layer : p.layers) {
    layer_pubs_[layer] = pnh.advertise<nav_msgs::OccupancyGrid>("layers/" + layer, 1, true);
  }
  where_srv_ = pnh.advertiseService("where_is", &BridgeNode::WhereIs, this);
  label_srv_ = pnh.advertiseService("label", &BridgeNode::Label, this);
  poll_timer_ = nh.createTimer(ros::Duration(p.poll_period_s), &BridgeNode::Poll, this);
  ROS_INFO("anchordb_ros: server %s:%d, map '%s' in frame '%s'", p.host.c_str(), p.port, p.map.c_str(),
           p.map_frame.c_str());
}

std::string BridgeNode::Finish() {
  session_.Finish();
  const SessionCounts& c = session_.counts();
  char line[320];
  std::snprintf(line, sizeof(line), "anchordb_ros: offered %ld, stored %ld (acknowledged), skipped %ld, dropped %ld, "
                "no tf %ld, scenes opened %ld closed %ld, server failures %ld", static_cast<long>(c.offered),
                static_cast<long>(c.stored), static_cast<long>(c.skipped_moving), static_cast<long>(c.dropped),
                static_cast<long>(tf_drops_), static_cast<long>(c.scenes_opened), static_cast<long>(c.scenes_closed),
                static_cast<long>(c.server_failures));
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
  const std::vector<std::uint16_t> depth = Millimetres(*image);
  if (depth.empty()) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: depth encoding '%s' not supported (16UC1, mono16, 32FC1)", image->encoding.c_str());
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
  const FrameOutcome outcome = session_.OnFrame(image->header.stamp.toSec(), IsometryOf(X.transform), *camera_, depth,
                                                ros::WallTime::now().toSec());
  if (outcome == FrameOutcome::kDropped) {
    ROS_WARN_THROTTLE(2.0, "anchordb_ros: frame not stored (%s); retrying in %.1f s", session_.last_error().c_str(),
                      session_.backoff_s());
  }
}

}  // namespace anchordb::ros_bridge
