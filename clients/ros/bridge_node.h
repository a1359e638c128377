#pragma once
// anchordb_ros: the ROS 1 bridge node (issue 32). Depth images (16UC1 / mono16 mm, 32FC1 m) with their CameraInfo,
// posed in the map frame through tf at each image's stamp (tf2_ros::MessageFilter), go through the observation rule
// into scene models on an anchordb server (SceneSession), each with the person mask of its stamp when ~mask_topic is
// set (mono8 / 8UC1, nonzero: a person; the frame's dynamic input); the map of ~grid_topic (nav_msgs/OccupancyGrid)
// becomes the occupancy layer ~grid_layer, as `anchordb import rosbag` makes them. What the memory learns comes back
// as ~events
// (anchordb_ros/ChangeEvent), ~instances (visualization_msgs/MarkerArray), ~status (std_msgs/String, JSON counts)
// ~layers/<name> (nav_msgs/OccupancyGrid of the probability layers named in ~layers) and the services ~where_is
// and ~label. C++17 (ROS 1's generated messages); no project C++20 header here.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <message_filters/subscriber.h>
#include <nav_msgs/OccupancyGrid.h>
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
  // Optional inputs (empty topic: off). A depth image waits at most mask_wait_s [s, wall clock] for the mask of its
  // stamp, then goes without one (counted).
  std::string mask_topic, grid_topic, grid_layer = "occupancy";
  double mask_wait_s = 0.5;
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
  // A depth image whose pose was looked up, waiting for its person mask (~mask_topic set).
  struct PendingDepth {
    sensor_msgs::Image::ConstPtr image;
    Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
    double arrived_wall_s = 0.0;
  };

  void OnInfo(const sensor_msgs::CameraInfo::ConstPtr& info);
  void OnDepth(const sensor_msgs::Image::ConstPtr& image);
  void OnMask(const sensor_msgs::Image::ConstPtr& mask);
  void OnGrid(const nav_msgs::OccupancyGrid::ConstPtr& grid);
  // Hands the waiting depth images on, in stamp order: each with its mask once that came, or without one after
  // mask_wait_s (all of them: every waiting image at once).
  void DrainPending(bool all);
  void Store(const sensor_msgs::Image& image, const Eigen::Isometry3d& X_MapCamera, const sensor_msgs::Image* mask);
  void ImportGrid();
  void Poll(const ros::TimerEvent&);
  void PrimeEvents();
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
  // Without its own thread (spin_thread false): tf messages are taken on the one spin thread, as the images are.
  // With the listener's thread, a transform arriving while tf2_ros::MessageFilter::add registers its request for an
  // image fires the request before the image is in the filter's list: the image then waits there for ever, neither
  // passed on nor reported as dropped (Debian 12's tf2_ros; seen as 1-2 of 94 bag images lost in 2 of 3 test runs).
  tf2_ros::TransformListener listener_;
  message_filters::Subscriber<sensor_msgs::Image> depth_sub_;
  tf2_ros::MessageFilter<sensor_msgs::Image> depth_filter_;
  ros::Subscriber info_sub_, mask_sub_, grid_sub_;
  ros::Publisher events_pub_, markers_pub_, status_pub_;
  ros::ServiceServer where_srv_, label_srv_;
  ros::Timer poll_timer_;
  std::optional<client::Camera> camera_;
  bool map_ready_ = false, events_primed_ = false;
  std::int64_t last_event_ = 0;
  std::map<std::string, ros::Publisher> layer_pubs_;
  std::map<std::string, std::int64_t> layer_versions_;  // the version last published
  std::int64_t tf_drops_ = 0;
  std::deque<PendingDepth> pending_;                         // in arrival (stamp) order
  std::map<std::uint64_t, sensor_msgs::Image::ConstPtr> masks_;  // by stamp [ns], not yet matched
  std::int64_t without_mask_ = 0;                            // depth images that went on without their mask
  std::int64_t masks_refused_ = 0;                           // masks of another size or encoding
  nav_msgs::OccupancyGrid::ConstPtr grid_;                   // received, not yet imported
  bool grid_done_ = false;                                   // imported (or the layer existed): later maps ignored
};

}  // namespace anchordb::ros_bridge
