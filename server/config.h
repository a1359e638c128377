#pragma once
// The server's typed configuration. Defaults live in the struct; values are loaded, in increasing precedence,
// from an optional JSON file (--config), environment variables ANCHORDB_<NAME> and command-line flags
// --name=value. Unknown keys in the file and unknown flags are errors; every setting has a description that
// GET /v1/settings serves.
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace anchordb::server {

struct Config {
  std::string db = "./var/anchordb.sqlite";
  std::string backup_dir;  // empty: "backups" beside the database file
  std::string bind = "127.0.0.1";
  int port = 8765;
  int threads = 32;
  std::string auth = "auto";
  std::string synchronous = "FULL";
  int busy_timeout_ms = 5000;
  int reader_connections = 4;
  std::int64_t max_body_bytes = 64ll << 20;
  std::int64_t max_map_pixels = 25'000'000;
  int max_polygons = 256;
  int max_polygon_vertices = 4096;
  int max_list_limit = 1000;
  int max_pending_writes = 64;
  bool log_requests = true;
  int occupied_min = 65;
  int free_max = 25;
  double attention_near_m = 1.0;
  double attention_max_facing_rad = 0.7854;
  double viewpoint_dilation_m = 1.0;
  double viewpoint_min_obstacle_m = 0.35;
  double viewpoint_robot_radius_m = 0.25;
  double viewpoint_min_surface_m = 0.5;
  double viewpoint_max_surface_m = 2.0;
  double viewpoint_min_person_m = 0.5;
  double viewpoint_spacing_m = 0.75;
  double viewpoint_travel_scale_m = 10.0;
  double viewpoint_weight_position = 0.7;
  double viewpoint_weight_travel = 0.3;
  std::int64_t viewpoint_seed = 42;
  int scene_persist_every_frames = 30;
  int scene_max_image_side = 4096;
  int scene_settle_frames = 8;
  double segment_cluster_tolerance_m = 0.025;
  int segment_min_points = 250;
  double segment_min_extent_m = 0.03;
  int merge_max_candidates = 5;
  double merge_max_age_s = 30.0 * 24 * 3600;
  double merge_candidate_radius_m = 6.0;
  double merge_min_overlap = 0.05;
  double merge_frustum_far_m = 5.0;
  double supersede_distance_m = 0.15;
  double supersede_angle_rad = 0.1745;
  int grounding_n_best = 100;
  double grounding_sigma = 3.0;
  double grounding_edge_max_gap_m = 1.5;
  double grounding_relation_sharpness = 3.0;
  int grounding_max_furniture = 64;
  std::string grounding_knowledge;
};

struct SettingInfo {
  std::string name;
  std::string type;  // int, number, string, bool
  std::string description;
};

// Every setting, in a stable order.
const std::vector<SettingInfo>& Settings();

// Loads a configuration from `args` (flags after the subcommand), the environment and the file named by
// --config. Throws std::invalid_argument with a message naming the bad key or value.
Config LoadConfig(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment);

// {"settings":[{"name","type","description","value"}]}
nlohmann::json SettingsJson(const Config& config);

// Text for --help.
std::string SettingsHelp();

bool IsLoopback(const std::string& bind);

}  // namespace anchordb::server
