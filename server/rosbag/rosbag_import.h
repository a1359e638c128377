#pragma once
// `anchordb import rosbag` (issue 32): a ROS 1 bag into a map through the scene, grid and octomap services, as the
// robot that recorded it would have stored it: the observation rule (engine/observation) decides from the depth
// images' optical-frame poses (tf, map frame) where the camera held still; there a scene model opens (with merge),
// takes every frame while the camera stays and closes when it leaves, after a pause of the stream or at the end. The
// bag is scanned whole (topics, encodings, sizes, tf) before anything is stored, so a bad bag leaves the database as
// it was. Each stored keyframe's change analysis is queued as the server queues it and run before the import returns,
// so the map has the change events the robot would have had. No ROS header here: the bag is read in rosbag_source.cc.
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "engine/observation/observation_rule.h"
#include "server/config.h"
#include "server/rosbag/rosbag_source.h"

namespace anchordb::server {

struct RosbagImportOptions {
  std::string bag;  // the .bag file
  std::string map;  // an existing map
  RosbagTopics topics;
  engine::ObservationRuleParams rule;
  std::string grid_layer = "occupancy";  // the occupancy layer the grid topic's last map becomes
  bool merge = true;                     // each new scene model merges earlier ones of its place (3.3.3)
};

// A change event the import's keyframe analyses wrote.
struct RosbagImportEvent {
  std::int64_t id = 0;
  std::string type;        // added | removed | moved
  std::string detection;   // observed | meanwhile
  std::int64_t instance = 0;  // 0: none
};

// What an import did (also printed as the summary's JSON).
struct RosbagImportSummary {
  std::int64_t frames_read = 0;        // depth images in the bag
  std::int64_t frames_used = 0;        // fed to a scene model
  std::int64_t skipped_every = 0;      // left out by --every
  std::int64_t skipped_no_pose = 0;    // no tf pose at the stamp
  std::int64_t skipped_moving = 0;     // the camera was moving or had not dwelt long enough
  std::int64_t skipped_stamp = 0;      // stamp not after the previous image's
  std::vector<std::int64_t> scenes;    // the scene models opened, in order
  std::int64_t keyframes = 0;
  std::int64_t frames_masked = 0;      // frames stored with a person mask (the mask topic's image of their stamp)
  std::int64_t dynamic_pixels = 0;     // dynamic pixels of the stored frames, as the scene service counted them
  std::int64_t analyses = 0;          // keyframe change analyses run
  std::int64_t analyses_failed = 0;   // queued analyses that failed or are still pending (the server retries them)
  std::vector<RosbagImportEvent> events;
  bool grid_imported = false;
  double seconds = 0.0;
};

// Throws std::invalid_argument for a bad bag (rosbag_source.h) or an unknown map, anchordb::Error when a service
// refuses a frame.
RosbagImportSummary ImportRosbag(const Config& config, const RosbagImportOptions& options, std::ostream& out);

// `anchordb import rosbag ...` arguments after "rosbag".
int ImportRosbagCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment);

}  // namespace anchordb::server
