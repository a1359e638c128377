#pragma once
// anchordb_ros: the ROS 1 bridge node (issue 32). Depth images (16UC1 / mono16 mm, 32FC1 m) with their CameraInfo,
// posed in the map frame through tf at each image's stamp (tf2_ros::MessageFilter), go through the observation rule
// into scene models on an anchordb server (SceneSession); what the memory learns comes back as ~events
// (anchordb_ros/ChangeEvent), ~instances (visualization_msgs/MarkerArray), ~status (std_msgs/String, JSON counts)
// ~layers/<name> (nav_msgs/OccupancyGrid of the probability layers named in ~layers) and the services ~where_is
// and ~label. C++17 (ROS 1's generated messages); no project C++20 header here.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <message_filters/subscriber.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include <anchordb_ros/Label.h>
#include <anchordb_ros/WhereIs.h>

#include "clients/ros/bridge_session.h"

namespace anchordb::ros_bridge {

struct NodeParams {
  std::string host = "127.0.0.1", token, map = "home", map_frame = "map";
  int port = 8765;
  double timeout_s = 5.0, poll_period_s = 1.0;
  bool create_map = true, publish_past_events = false;
  std::vector<std::string> layers;  // probability layers published as ~layers/<name> (~layers: "a,b")
  SessionSettings session;
};

// The node's private parameters (~server_host, ~server_port, ~token, ~map, ~map_frame, ...) with these defaults.
NodeParams LoadParams(const ros::NodeHandle& pnh);

class BridgeNode {
 public:
  BridgeNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& p);
  // Closes the open model; the counts as one line (main prints it at exit: rosconsole is gone after shutdown).
  std::string Finish();

 private:
  void OnInfo(const sensor_msgs::CameraInfo::ConstPtr& info);
  void OnDepth(const sensor_msgs::Image::ConstPtr& image);
  void Poll(const ros::TimerEvent&);
  void PublishEvents();
  void PublishMarkers();
  void PublishStatus();
  void PublishLayers();
  bool EnsureMap();
  bool WhereIs(anchordb_ros::WhereIs::Request& req, anchordb_ros::WhereIs::Response& res);
  bool Label(anchordb_ros::Label::Request& req, anchordb_ros::Label::Response& res);

  NodeParams p_;
  client::Client frames_client_;  // the session's
  client::Client query_client_;   // polls and services
  SceneSession session_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener listener_;
  message_filters::Subscriber<sensor_msgs::Image> depth_sub_;
  tf2_ros::MessageFilter<sensor_msgs::Image> depth_filter_;
  ros::Subscriber info_sub_;
  ros::Publisher events_pub_, markers_pub_, status_pub_;
  ros::ServiceServer where_srv_, label_srv_;
  ros::Timer poll_timer_;
  std::optional<client::Camera> camera_;
  bool map_ready_ = false, events_primed_ = false;
  std::int64_t last_event_ = 0;
  std::map<std::string, ros::Publisher> layer_pubs_;
  std::map<std::string, std::int64_t> layer_versions_;  // the version last published
  std::int64_t tf_drops_ = 0;
};

}  // namespace anchordb::ros_bridge
