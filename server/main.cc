// anchordb: the spatial memory server. Subcommands: serve, token create, forget, backup, version.
#include <malloc.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "api/event_routes.h"
#include "api/furniture_routes.h"
#include "api/grid_routes.h"
#include "api/http_api.h"
#include "api/job_json.h"
#include "api/job_routes.h"
#include "api/scene_routes.h"
#include "schema/error.h"
#include "server/auth.h"
#include "server/config.h"
#include "services/jobs/forget_job.h"
#include "storage/backup.h"
#include "storage/forgetting.h"
#include "storage/repositories.h"
#include "storage/store.h"

#include <httplib.h>  // after Eigen (see api/http_api.h)

extern char** environ;

namespace anchordb::server {
namespace {

std::mutex g_log_mutex;

void Log(const std::string& line) {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  char ts[32];
  std::strftime(ts, sizeof(ts), "%Y-%m-%dT%H:%M:%S", std::gmtime(&t));
  std::lock_guard<std::mutex> lock(g_log_mutex);
  std::fprintf(stderr, "%s.%03lldZ %s\n", ts, static_cast<long long>(ms), line.c_str());
}

std::map<std::string, std::string> Environment() {
  std::map<std::string, std::string> env;
  for (char** e = environ; *e; ++e) {
    std::string kv(*e);
    const auto eq = kv.find('=');
    if (eq != std::string::npos && kv.rfind("ANCHORDB_", 0) == 0) env[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return env;
}

// The directory of online backups, absolute (job requests name the file a client will look for): the setting,
// or "backups" beside the database file.
std::string BackupDir(const Config& c) {
  const std::filesystem::path dir = c.backup_dir.empty() ? std::filesystem::path(c.db).parent_path() / "backups"
                                                         : std::filesystem::path(c.backup_dir);
  return std::filesystem::absolute(dir).lexically_normal().string();
}

storage::StoreOptions StoreOptionsOf(const Config& c) {
  storage::StoreOptions o;
  o.path = c.db;
  o.connection.busy_timeout_ms = c.busy_timeout_ms;
  o.connection.synchronous = c.synchronous;
  o.reader_connections = c.reader_connections;
  return o;
}

int Serve(const Config& config) {
  // glibc gives freed memory back to the kernel eagerly (madvise per thread arena): under concurrent short requests
  // that is page faults and TLB shootdowns on every request. A server keeps what it had.
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  const bool loopback = IsLoopback(config.bind);
  if (!loopback && config.auth == "off") {
    std::cerr << "anchordb: refusing to serve " << config.bind << " with auth=off; only loopback may run open\n";
    return 2;
  }
  // Signals are handled by one thread with sigwait; block them before any other thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  storage::Store store(StoreOptionsOf(config));
  const auto& report = store.migration_report();
  for (const auto& name : report.applied) Log("migration applied: " + name);
  const bool auth_required = config.auth == "required" || !loopback;
  if (auth_required) {
    const auto tokens = store.Read([](storage::Connection& c) { return storage::CountTokens(c); });
    if (tokens == 0) {
      std::cerr << "anchordb: binding " << config.bind << " requires API tokens and the database has none; create one "
                << "with: anchordb token create --role admin --db " << config.db << "\n";
      return 2;
    }
  }

  services::ServiceLimits limits;
  limits.max_map_pixels = static_cast<std::size_t>(config.max_map_pixels);
  limits.max_polygons = static_cast<std::size_t>(config.max_polygons);
  limits.max_polygon_vertices = static_cast<std::size_t>(config.max_polygon_vertices);
  limits.max_list_limit = config.max_list_limit;
  services::GridDefaults defaults;
  defaults.occupancy = {config.occupied_min, config.free_max};
  defaults.attention = {config.attention_near_m, config.attention_max_facing_rad};
  auto& v = defaults.viewpoints;
  v.dilation_radius_m = config.viewpoint_dilation_m;
  v.min_obstacle_distance_m = config.viewpoint_min_obstacle_m;
  v.robot_radius_m = config.viewpoint_robot_radius_m;
  v.min_surface_distance_m = config.viewpoint_min_surface_m;
  v.max_surface_distance_m = config.viewpoint_max_surface_m;
  v.min_person_distance_m = config.viewpoint_min_person_m;
  v.cluster_spacing_m = config.viewpoint_spacing_m;
  v.travel_scale_m = config.viewpoint_travel_scale_m;
  v.weight_position = config.viewpoint_weight_position;
  v.weight_travel = config.viewpoint_weight_travel;
  v.seed = static_cast<std::uint64_t>(config.viewpoint_seed);
  services::GridService service(store, limits, defaults);
  services::SceneLimits scene_limits;
  scene_limits.persist_every_frames = config.scene_persist_every_frames;
  scene_limits.max_image_side = config.scene_max_image_side;
  scene_limits.settle_frames = config.scene_settle_frames;
  services::MergeSettings merge;
  merge.max_candidates = config.merge_max_candidates;
  merge.max_age_s = config.merge_max_age_s;
  merge.candidate_radius_m = config.merge_candidate_radius_m;
  merge.min_overlap = config.merge_min_overlap;
  merge.frustum_far_m = config.merge_frustum_far_m;
  merge.supersede_distance_m = config.supersede_distance_m;
  merge.supersede_angle_rad = config.supersede_angle_rad;
  services::SceneService scenes(store, scene_limits, merge);
  services::FurnitureSettings furniture_settings;
  furniture_settings.n_best = config.grounding_n_best;
  furniture_settings.sigma = config.grounding_sigma;
  furniture_settings.edge_max_gap_m = config.grounding_edge_max_gap_m;
  furniture_settings.relation_sharpness = config.grounding_relation_sharpness;
  furniture_settings.max_furniture = config.grounding_max_furniture;
  if (!config.grounding_knowledge.empty()) {
    std::ifstream in(config.grounding_knowledge);
    if (!in) {
      std::cerr << "anchordb: cannot read grounding_knowledge file " << config.grounding_knowledge << "\n";
      return 2;
    }
    furniture_settings.knowledge_json.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  services::FurnitureService furniture(store, furniture_settings);
  services::EventSettings event_settings;
  event_settings.change.segments.cluster_tolerance_m = config.segment_cluster_tolerance_m;
  event_settings.change.segments.min_points = config.segment_min_points;
  event_settings.change.segments.min_extent_m = config.segment_min_extent_m;
  services::EventService events(store, &furniture, event_settings);
  scenes.SetKeyframeListener(&events);

  api::HttpOptions options;
  options.auth_required = auth_required;
  options.authenticate = [&store](const std::string& token) -> std::optional<api::Role> {
    const auto record = store.Read([&](storage::Connection& c) { return storage::FindTokenByHash(c, Sha256Hex(token)); });
    if (!record) return std::nullopt;
    return api::RoleFromName(record->role);
  };
  if (config.log_requests) options.log = Log;
  options.settings = [config] { return SettingsJson(config); };
  options.max_body_bytes = static_cast<std::size_t>(config.max_body_bytes);
  options.max_pending_writes = config.max_pending_writes;
  services::JobSettings job_settings;
  job_settings.synchronous = config.synchronous;
  job_settings.backup_dir = BackupDir(config);
  services::JobService jobs(store, job_settings);
  if (jobs.interrupted_at_start() > 0) {
    Log("jobs interrupted by the previous stop, marked failed: " + std::to_string(jobs.interrupted_at_start()));
  }
  api::HttpApi http(options);
  api::RegisterGridRoutes(http.router(), service);
  api::RegisterSceneRoutes(http.router(), scenes);
  api::RegisterFurnitureRoutes(http.router(), furniture);
  api::RegisterEventRoutes(http.router(), events);
  api::RegisterJobRoutes(http.router(), jobs);

  httplib::Server server;
  const int threads = config.threads;
  server.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
  server.set_keep_alive_max_count(100000);
  // Without TCP_NODELAY, headers and body leave in two writes and every kept-alive request waits ~40 ms for
  // the peer's delayed ACK (measured by bench/: 180 req/s instead of 16,000).
  server.set_tcp_nodelay(true);
  server.set_read_timeout(10, 0);
  http.Mount(server);

  const int port = config.port == 0 ? server.bind_to_any_port(config.bind) : (server.bind_to_port(config.bind, config.port) ? config.port : -1);
  if (port < 0) {
    std::cerr << "anchordb: cannot listen on " << config.bind << ":" << config.port << "\n";
    return 1;
  }
  std::thread signal_thread([&server, signals] {
    int received = 0;
    sigwait(&signals, &received);
    Log(std::string("received ") + (received == SIGINT ? "SIGINT" : "SIGTERM") + ", shutting down");
    server.stop();
  });
  std::printf("anchordb listening on http://%s:%d (db %s, schema version %d, auth %s)\n", config.bind.c_str(), port,
              config.db.c_str(), report.to_version, auth_required ? "required" : "off (loopback)");
  std::fflush(stdout);
  const bool ok = server.listen_after_bind();
  if (signal_thread.joinable()) {
    pthread_kill(signal_thread.native_handle(), SIGTERM);  // wakes sigwait if the server stopped for another reason
    signal_thread.join();
  }
  scenes.PersistAll();
  Log("stopped; scene models persisted, database closed cleanly");
  return ok ? 0 : 1;
}

// A subcommand's own option `name` at args[i], as "--name VALUE" (i moves past the value) or "--name=VALUE".
bool TakeOption(const std::vector<std::string>& args, std::size_t& i, const std::string& name, std::string& value) {
  const std::string& a = args[i];
  if (a == name) {
    if (i + 1 >= args.size()) throw std::invalid_argument(name + " needs a value");
    value = args[++i];
    return true;
  }
  if (a.rfind(name + "=", 0) == 0) {
    value = a.substr(name.size() + 1);
    return true;
  }
  return false;
}

// anchordb backup --db FILE [--out FILE | --label ID]: an online copy of the database (the server may be running
// and writing); prints the report as JSON. Bad input: exit 2.
int BackupCommand(const std::vector<std::string>& args) {
  std::string out, label;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (!TakeOption(args, i, "--out", out) && !TakeOption(args, i, "--label", label)) rest.push_back(args[i]);
  }
  const Config config = LoadConfig(rest, Environment());
  if (!label.empty() && !json::IsValidId(label)) throw std::invalid_argument("--label: not a valid id: " + label);
  if (!std::filesystem::exists(config.db)) throw std::invalid_argument("no database at " + config.db);
  if (out.empty()) {
    const std::int64_t now_ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    out = storage::BackupFileName(BackupDir(config), config.db, now_ns, label);
  }
  if (std::filesystem::exists(out)) throw std::invalid_argument("--out: " + out + " exists already");
  const storage::BackupReport report = storage::Backup(config.db, out, config.busy_timeout_ms);
  std::cout << report.ToJson().dump(1) << "\n";
  return 0;
}

// anchordb forget --db FILE --map ID [--policy JSON] [--dry-run] [--vacuum]: one forgetting run (for cron); prints
// the report as JSON. Bad input: exit 2 with the error on stderr.
int Forget(const std::vector<std::string>& args) {
  std::string map, policy_text;
  bool dry_run = false, vacuum = false;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (TakeOption(args, i, "--map", map) || TakeOption(args, i, "--policy", policy_text)) continue;
    if (args[i] == "--dry-run") dry_run = true;
    else if (args[i] == "--vacuum") vacuum = true;
    else rest.push_back(args[i]);
  }
  if (map.empty()) throw std::invalid_argument("forget needs --map ID");
  const Config config = LoadConfig(rest, Environment());
  try {
    json::CheckId(map, "map");
  } catch (const Error& e) {
    throw std::invalid_argument(std::string("--map: ") + e.what());
  }
  storage::ForgetRequest request;
  try {
    json::Json body = json::Json::object();
    if (!policy_text.empty()) body["policy"] = json::ParseObject(policy_text);
    body["dry_run"] = dry_run;
    request = api::ParseForgetRequest(body);
    services::CheckForgetRequest(request, SystemClock::Instance().NowNs());
    if (vacuum) request.policy.vacuum = true;
  } catch (const Error& e) {
    throw std::invalid_argument(std::string("--policy: ") + e.what());
  }
  const storage::StoreOptions options = StoreOptionsOf(config);
  storage::Store store(options);  // migrates the file first
  storage::Connection connection(config.db, options.connection);
  const std::int64_t now_ns = request.now_ns.value_or(SystemClock::Instance().NowNs());
  storage::ForgetReport report;
  try {
    report = storage::Forget(connection, map, request.policy, now_ns, request.dry_run);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kNotFound) throw std::invalid_argument(e.what());
    throw;
  }
  std::cout << report.ToJson().dump(1) << "\n";
  return 0;
}

void Usage() {
  std::cout << "usage:\n"
               "  anchordb serve [--config file.json] [--<setting>=<value> ...]\n"
               "  anchordb token create --role reader|writer|admin [--db file]\n"
               "  anchordb forget --db file --map ID [--policy JSON] [--dry-run] [--vacuum]\n"
               "  anchordb backup --db file [--out file | --label ID]\n"
               "  anchordb version\n\nsettings (also ANCHORDB_<NAME> environment variables):\n"
            << SettingsHelp();
}

int Main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    Usage();
    return args.empty() ? 2 : 0;
  }
  try {
    if (args[0] == "version") {
      std::cout << "anchordb 0.1.0\n";
      return 0;
    }
    if (args[0] == "serve") {
      std::vector<std::string> rest(args.begin() + 1, args.end());
      for (const auto& a : rest) {
        if (a == "--help" || a == "-h") return Usage(), 0;
      }
      return Serve(LoadConfig(rest, Environment()));
    }
    if (args[0] == "forget") return Forget(std::vector<std::string>(args.begin() + 1, args.end()));
    if (args[0] == "backup") return BackupCommand(std::vector<std::string>(args.begin() + 1, args.end()));
    if (args.size() >= 2 && args[0] == "token" && args[1] == "create") {
      std::string role;
      std::vector<std::string> rest;
      for (std::size_t i = 2; i < args.size(); ++i) {
        if (args[i] == "--role" && i + 1 < args.size()) role = args[++i];
        else if (args[i].rfind("--role=", 0) == 0) role = args[i].substr(7);
        else rest.push_back(args[i]);
      }
      const Config config = LoadConfig(rest, Environment());
      storage::Store store(StoreOptionsOf(config));
      const CreatedToken t = CreateToken(store, role);
      std::cout << "token " << t.id << " (" << t.role << "): " << t.secret << "\n"
                << "Store it now: only its hash is kept in " << config.db << ".\n";
      return 0;
    }
    std::cerr << "anchordb: unknown command '" << args[0] << "'\n";
    Usage();
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "anchordb: " << e.what() << "\n";
    return 2;
  } catch (const Error& e) {
    std::cerr << "anchordb: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace
}  // namespace anchordb::server

int main(int argc, char** argv) { return anchordb::server::Main(argc, argv); }
