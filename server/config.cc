#include "server/config.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace anchordb::server {
namespace {

struct Binding {
  SettingInfo info;
  std::function<void(Config&, const std::string& text)> set;
  std::function<nlohmann::json(const Config&)> get;
};

template <typename T>
Binding Bind(std::string name, std::string description, T Config::*field, double lo = -1e300, double hi = 1e300) {
  Binding b;
  std::string type = std::is_same_v<T, std::string> ? "string" : std::is_same_v<T, bool> ? "bool"
                     : std::is_integral_v<T> ? "int" : "number";
  b.info = {name, type, std::move(description)};
  b.set = [name, field, lo, hi](Config& c, const std::string& text) {
    if constexpr (std::is_same_v<T, std::string>) {
      c.*field = text;
    } else if constexpr (std::is_same_v<T, bool>) {
      if (text == "true" || text == "1") c.*field = true;
      else if (text == "false" || text == "0") c.*field = false;
      else throw std::invalid_argument("setting " + name + ": '" + text + "' is not true or false");
    } else {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
        throw std::invalid_argument("setting " + name + ": '" + text + "' is not a number");
      }
      if (std::is_integral_v<T> && v != std::floor(v)) throw std::invalid_argument("setting " + name + ": must be an integer");
      if (v < lo || v > hi) {
        std::ostringstream m;
        m << "setting " << name << ": " << text << " is outside [" << lo << ", " << hi << "]";
        throw std::invalid_argument(m.str());
      }
      c.*field = static_cast<T>(v);
    }
  };
  b.get = [field](const Config& c) { return nlohmann::json(c.*field); };
  return b;
}

const std::vector<Binding>& Bindings() {
  static const std::vector<Binding> kBindings = {
      Bind("db", "SQLite database file (created and migrated at start-up)", &Config::db),
      Bind("backup_dir", "directory of the online backups (POST /v1/backups); empty: 'backups' beside the database",
           &Config::backup_dir),
      Bind("bind", "address to listen on; any non-loopback address requires API tokens", &Config::bind),
      Bind("port", "TCP port (0 = any free port, printed at start-up)", &Config::port, 0, 65535),
      Bind("threads", "HTTP worker threads; cpp-httplib holds one per open keep-alive connection, so this bounds the "
                      "connections served at once", &Config::threads, 1, 1024),
      Bind("auth", "auto (open on loopback, tokens required elsewhere), required, or off (loopback only)", &Config::auth),
      Bind("synchronous", "SQLite synchronous mode: FULL (fsync every commit) or NORMAL", &Config::synchronous),
      Bind("busy_timeout_ms", "how long SQLite waits for a lock before giving up [ms]", &Config::busy_timeout_ms, 0, 600000),
      Bind("reader_connections", "read-only SQLite connections in the pool", &Config::reader_connections, 1, 64),
      Bind("max_body_bytes", "largest accepted request body [bytes]", &Config::max_body_bytes, 1024, 4e9),
      Bind("max_map_pixels", "largest accepted map image [pixels]", &Config::max_map_pixels, 1, 4e8),
      Bind("max_polygons", "most polygons in one request", &Config::max_polygons, 1, 1e6),
      Bind("max_polygon_vertices", "most vertices in one polygon", &Config::max_polygon_vertices, 3, 1e7),
      Bind("max_list_limit", "largest page size of list routes", &Config::max_list_limit, 1, 1e6),
      Bind("max_pending_writes", "writes allowed to wait for the writer before 503", &Config::max_pending_writes, 1, 1e6),
      Bind("log_requests", "log one line per request to stderr", &Config::log_requests),
      Bind("occupied_min", "occupancy value (0-100) from which a cell blocks sight and motion", &Config::occupied_min, 1, 100),
      Bind("free_max", "occupancy value (0-100) up to which a cell is known free", &Config::free_max, 0, 99),
      Bind("attention_near_m", "distance person-surface that counts as next to it [m]", &Config::attention_near_m, 0, 100),
      Bind("attention_max_facing_rad", "largest angle between heading and surface that counts as facing it [rad]",
           &Config::attention_max_facing_rad, 0, 3.1416),
      Bind("viewpoint_dilation_m", "radius of the dilation around the surface (thesis: ~1 m) [m]", &Config::viewpoint_dilation_m, 0.05, 10),
      Bind("viewpoint_min_obstacle_m", "clearance a viewpoint keeps from obstacles [m]", &Config::viewpoint_min_obstacle_m, 0, 10),
      Bind("viewpoint_robot_radius_m", "clearance of the path the robot drives [m]", &Config::viewpoint_robot_radius_m, 0, 5),
      Bind("viewpoint_min_surface_m", "nearest a viewpoint may be to the surface [m]", &Config::viewpoint_min_surface_m, 0, 10),
      Bind("viewpoint_max_surface_m", "farthest a viewpoint may be from the surface [m]", &Config::viewpoint_max_surface_m, 0, 20),
      Bind("viewpoint_min_person_m", "nearest a viewpoint may be to the person [m]", &Config::viewpoint_min_person_m, 0, 10),
      Bind("viewpoint_spacing_m", "boundary length per k-means cluster [m]", &Config::viewpoint_spacing_m, 0.05, 100),
      Bind("viewpoint_travel_scale_m", "travel distance at which the travel score halves [m]", &Config::viewpoint_travel_scale_m, 0.01, 1e4),
      Bind("viewpoint_weight_position", "weight of the position-relative-to-person score", &Config::viewpoint_weight_position, 0, 1),
      Bind("viewpoint_weight_travel", "weight of the travel score", &Config::viewpoint_weight_travel, 0, 1),
      Bind("viewpoint_seed", "seed of the k-means initialisation", &Config::viewpoint_seed, 0, 9.0e15),
      Bind("scene_persist_every_frames", "frames between checkpoints of an observing scene model (1 = every frame durable)",
           &Config::scene_persist_every_frames, 1, 1e6),
      Bind("scene_max_image_side", "largest camera width or height of a scene model [px]", &Config::scene_max_image_side, 1, 16384),
      Bind("scene_settle_frames", "steady frames after a change of the movable layer that make a 'settled' keyframe "
           "(a completed movement, new action layer); 0 = off", &Config::scene_settle_frames, 0, 1e6),
      Bind("segment_cluster_tolerance_m", "Euclidean clustering of movable points: neighbour distance [m]",
           &Config::segment_cluster_tolerance_m, 0.001, 1.0),
      Bind("segment_min_points", "smallest segment (movable pixels) that makes a change event", &Config::segment_min_points, 1, 1e7),
      Bind("segment_min_extent_m", "smallest largest side of a segment's bounding box [m]", &Config::segment_min_extent_m, 0.0, 10.0),
      Bind("merge_max_candidates", "most earlier scene models merged into a new one (newest first)", &Config::merge_max_candidates, 0, 100),
      Bind("merge_max_age_s", "earlier scene models older than this are not merged [s]", &Config::merge_max_age_s, 0, 1e10),
      Bind("merge_candidate_radius_m", "earlier cameras farther than this from the new one are not merged [m]",
           &Config::merge_candidate_radius_m, 0, 1000),
      Bind("merge_min_overlap", "fraction of an earlier background that must lie in the new view frustum", &Config::merge_min_overlap, 0, 1),
      Bind("merge_frustum_far_m", "rear boundary of a view frustum, for overlap and rear projection [m]", &Config::merge_frustum_far_m, 0.5, 50),
      Bind("supersede_distance_m", "a new scene model this close to an earlier one (and looking alike) supersedes it [m]",
           &Config::supersede_distance_m, 0, 10),
      Bind("supersede_angle_rad", "largest angle between viewing directions for supersession [rad]", &Config::supersede_angle_rad, 0, 3.1416),
      Bind("grounding_n_best", "hypotheses (graph, match) a furniture graph keeps per description (thesis 5.3.3; default of "
                               "params.n_best)", &Config::grounding_n_best, 1, 2000),
      Bind("grounding_sigma", "damping of the grounding update p += (p_verbal - p) / sigma (thesis eq. 5.4; 1 = replace)",
           &Config::grounding_sigma, 1, 1000),
      Bind("grounding_edge_max_gap_m", "furniture pieces whose footprints are at most this far apart share a graph edge [m]",
           &Config::grounding_edge_max_gap_m, 0, 100),
      Bind("grounding_relation_sharpness", "kappa of the initial relation distribution p(r) ∝ exp(kappa cos(angle))",
           &Config::grounding_relation_sharpness, 0, 100),
      Bind("grounding_max_furniture", "most furniture pieces in one furniture graph", &Config::grounding_max_furniture, 2, 1000),
      Bind("grounding_knowledge", "JSON file {categories, frame_prior} replacing the built-in grounding tables "
                                  "(engine/grounding/*.json); empty = built in", &Config::grounding_knowledge),
  };
  return kBindings;
}

const Binding* Find(const std::string& raw) {
  std::string name = raw;
  for (char& c : name) c = c == '-' ? '_' : c;
  for (const Binding& b : Bindings()) {
    if (b.info.name == name) return &b;
  }
  return nullptr;
}

void Validate(const Config& c) {
  if (c.auth != "auto" && c.auth != "required" && c.auth != "off") {
    throw std::invalid_argument("setting auth: must be auto, required or off");
  }
  if (c.synchronous != "FULL" && c.synchronous != "NORMAL") {
    throw std::invalid_argument("setting synchronous: must be FULL or NORMAL");
  }
  if (c.free_max >= c.occupied_min) throw std::invalid_argument("settings: free_max must be below occupied_min");
  if (c.viewpoint_min_surface_m > c.viewpoint_max_surface_m) {
    throw std::invalid_argument("settings: viewpoint_min_surface_m exceeds viewpoint_max_surface_m");
  }
}

}  // namespace

const std::vector<SettingInfo>& Settings() {
  static const std::vector<SettingInfo> kInfos = [] {
    std::vector<SettingInfo> v;
    for (const Binding& b : Bindings()) v.push_back(b.info);
    return v;
  }();
  return kInfos;
}

bool IsLoopback(const std::string& bind) {
  return bind == "localhost" || bind == "::1" || bind.rfind("127.", 0) == 0;
}

Config LoadConfig(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment) {
  Config config;
  // Split flags into (name, value) first so --config can be honoured before the others.
  std::vector<std::pair<std::string, std::string>> flags;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) throw std::invalid_argument("unexpected argument '" + a + "'");
    const auto eq = a.find('=');
    if (eq != std::string::npos) {
      flags.emplace_back(a.substr(2, eq - 2), a.substr(eq + 1));
    } else {
      if (i + 1 >= args.size()) throw std::invalid_argument("flag " + a + " needs a value");
      flags.emplace_back(a.substr(2), args[++i]);
    }
  }
  for (const auto& [name, value] : flags) {
    if (name != "config") continue;
    std::ifstream in(value);
    if (!in) throw std::invalid_argument("cannot read config file " + value);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw std::invalid_argument("config file " + value + " is not a JSON object");
    for (const auto& [key, v] : j.items()) {
      const Binding* b = Find(key);
      if (!b) throw std::invalid_argument("config file " + value + ": unknown setting '" + key + "'");
      b->set(config, v.is_string() ? v.get<std::string>() : v.dump());
    }
  }
  for (const Binding& b : Bindings()) {
    std::string env_name = "ANCHORDB_";
    for (char c : b.info.name) env_name += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (auto it = environment.find(env_name); it != environment.end()) b.set(config, it->second);
  }
  for (const auto& [name, value] : flags) {
    if (name == "config") continue;
    const Binding* b = Find(name);
    if (!b) throw std::invalid_argument("unknown flag --" + name + " (see --help)");
    b->set(config, value);
  }
  Validate(config);
  return config;
}

nlohmann::json SettingsJson(const Config& config) {
  nlohmann::json out = {{"settings", nlohmann::json::array()}};
  for (const Binding& b : Bindings()) {
    out["settings"].push_back({{"name", b.info.name}, {"type", b.info.type}, {"description", b.info.description},
                               {"value", b.get(config)}});
  }
  return out;
}

std::string SettingsHelp() {
  const Config defaults;
  std::string out;
  for (const Binding& b : Bindings()) {
    out += "  --" + b.info.name + "=<" + b.info.type + ">  " + b.info.description + " (default " + b.get(defaults).dump() + ")\n";
  }
  return out;
}

}  // namespace anchordb::server
