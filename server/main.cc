// anchordb: the spatial memory server. Subcommands: serve, token create, forget, backup, import tum, version.
#include <malloc.h>
#include <sched.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "api/http_api.h"
#include "api/job_json.h"
#include "api/event_json.h"
#include "api/routes.h"
#include "schema/error.h"
#include "server/auth.h"
#include "server/config.h"
#include "server/http_serving.h"
#include "server/migrate_command.h"
#include "server/tum_import.h"
#ifdef ANCHORDB_WITH_ROSBAG
#include "server/rosbag/rosbag_import.h"
#endif
#include "services/audit/audit_service.h"
#include "services/jobs/forget_job.h"
#include "storage/backup.h"
#include "storage/forgetting.h"
#include "storage/repositories.h"
#include "storage/store.h"


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
std::string BackupDir(const ServerOptions& c) {
  const std::filesystem::path dir = c.backup_dir.empty() ? std::filesystem::path(c.db).parent_path() / "backups"
                                                         : std::filesystem::path(c.backup_dir);
  return std::filesystem::absolute(dir).lexically_normal().string();
}

// Signals are handled by one thread with sigwait: blocked here, before any other thread starts. Answers the set.
sigset_t BlockStopSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGPIPE, SIG_IGN);
  return signals;
}

// The capabilities' options from the configuration; nullopt (after saying why) when the grounding knowledge file
// cannot be read.
std::optional<services::CapabilityOptions> CapabilityOptionsOf(const Config& config) {
  const ServerOptions& o = config.server;
  services::CapabilityOptions capability_options = config.capabilities;
  capability_options.jobs.synchronous = o.synchronous;
  capability_options.jobs.backup_dir = BackupDir(o);
  if (!o.grounding_knowledge.empty()) {
    std::ifstream in(o.grounding_knowledge);
    if (!in) {
      std::cerr << "anchordb: cannot read grounding_knowledge file " << o.grounding_knowledge << "\n";
      return std::nullopt;
    }
    capability_options.furniture.knowledge_json.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return capability_options;
}

// What the previous stop left: jobs it interrupted (marked failed), keyframe analyses still queued (resumed with the
// workers, which start here) and OctoMaps behind their maps' keyframes (caught up).
void ResumeAtStart(storage::Store& store, services::Capabilities& capabilities) {
  if (capabilities.jobs.interrupted_at_start() > 0) {
    Log("jobs interrupted by the previous stop, marked failed: " + std::to_string(capabilities.jobs.interrupted_at_start()));
  }
  capabilities.analysis.Start();
  if (const auto queued = capabilities.analysis.View(std::nullopt); queued.pending > 0) {
    Log("keyframe analyses queued at start, resuming: " + std::to_string(queued.pending));
  }
  std::vector<std::string> maps;
  for (std::string after;;) {
    const auto page = store.Read([&](storage::Connection& c) { return storage::ListMaps(c, after, 500); });
    for (const auto& m : page) maps.push_back(m.id);
    if (page.size() < 500) break;
    after = page.back().id;
  }
  capabilities.octomap_feed.FollowAtStart(maps);
}

api::HttpOptions HttpOptionsOf(const Config& config, bool auth_required, storage::Store& store, HttpServing& serving,
                               services::Capabilities& capabilities) {
  api::HttpOptions options;
  options.auth_required = auth_required;
  options.authenticate = [&store](const std::string& token) -> std::optional<api::Caller> {
    const auto found = Authenticate(store, token);
    if (!found) return std::nullopt;
    return api::Caller{found->id, api::RoleFromName(found->role)};
  };
  if (config.server.log_requests) options.log = Log;
  options.settings = [config] { return SettingsJson(config); };
  options.extra_metrics = [&serving, &capabilities] {
    return serving.PrometheusText() + api::AnalysisMetricsText(capabilities.analysis.View(std::nullopt), capabilities.analysis.counters());
  };
  options.max_body_bytes = static_cast<std::size_t>(config.server.max_body_bytes);
  options.max_pending_writes = config.server.max_pending_writes;
  return options;
}

// Serves until SIGINT or SIGTERM (or a failure of the serving loop); false on a failure.
bool ServeUntilStopped(HttpServing& serving, const sigset_t& signals) {
  std::thread signal_thread([&serving, signals] {
    int received = 0;
    sigwait(&signals, &received);
    Log(std::string("received ") + (received == SIGINT ? "SIGINT" : "SIGTERM") + ", shutting down");
    serving.Stop();
  });
  bool ok = true;
  try {
    serving.Run();
  } catch (const std::exception& e) {
    Log(std::string("serving failed: ") + e.what());
    ok = false;
  }
  if (signal_thread.joinable()) {
    pthread_kill(signal_thread.native_handle(), SIGTERM);  // wakes sigwait if the server stopped for another reason
    signal_thread.join();
  }
  return ok;
}

// The cores this process may run on (its affinity mask, e.g. a container's cpuset), at least 1.
int UsableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return std::max(1u, std::thread::hardware_concurrency());
  return std::max(1, CPU_COUNT(&set));
}

int Serve(const Config& config) {
  const ServerOptions& o = config.server;
  // glibc gives freed memory back to the kernel eagerly (madvise per thread arena): under concurrent short requests
  // that is page faults and TLB shootdowns on every request. A server keeps what it had.
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  // Each arena keeps its own high-water mark, and glibc makes up to 8 per core: under 32 workers the resident memory
  // kept creeping up for minutes of a steady load (scripts/soak). Fewer arenas share theirs. An operator's own
  // MALLOC_ARENA_MAX or GLIBC_TUNABLES is left alone unless the setting is given.
  if (o.malloc_arenas > 0 || (!std::getenv("MALLOC_ARENA_MAX") && !std::getenv("GLIBC_TUNABLES"))) {
    mallopt(M_ARENA_MAX, o.malloc_arenas > 0 ? o.malloc_arenas : std::max(4, 2 * UsableCores()));
  }
  const bool loopback = IsLoopback(o.bind);
  if (!loopback && o.auth == "off") {
    std::cerr << "anchordb: refusing to serve " << o.bind << " with auth=off; only loopback may run open\n";
    return 2;
  }
  const sigset_t signals = BlockStopSignals();
  storage::Store store(StoreOptionsOf(o));
  const auto& report = store.migration_report();
  for (const auto& name : report.applied) Log("migration applied: " + name);
  const bool auth_required = o.auth == "required" || !loopback;
  if (auth_required && store.Read([](storage::Connection& c) { return storage::CountTokens(c); }) == 0) {
    std::cerr << "anchordb: binding " << o.bind << " requires API tokens and the database has none; create one "
              << "with: anchordb token create --role admin --db " << o.db << "\n";
    return 2;
  }
  const std::optional<services::CapabilityOptions> capability_options = CapabilityOptionsOf(config);
  if (!capability_options) return 2;
  services::Capabilities capabilities(store, *capability_options);
  ResumeAtStart(store, capabilities);
  ServingLimits limits;
  limits.worker_threads = o.threads;
  limits.max_connections = o.max_connections;
  limits.max_queued_requests = o.max_queued_requests;
  limits.idle_timeout_s = o.idle_timeout_s;
  HttpServing serving(limits);
  api::HttpApi http(HttpOptionsOf(config, auth_required, store, serving, capabilities));
  api::RegisterAllRoutes(http.router(), capabilities);
  // Every accepted socket gets TCP_NODELAY (server/http_serving.cc): without it, headers and body leave in two
  // writes and every kept-alive request waits ~40 ms for the peer's delayed ACK.
  http.Mount(serving.routes());
  int port = -1;
  try {
    port = serving.Bind(o.bind, o.port);
  } catch (const std::runtime_error& e) {
    std::cerr << "anchordb: " << e.what() << "\n";
    return 1;
  }
  std::printf("anchordb listening on http://%s:%d (db %s, schema version %d, auth %s)\n", o.bind.c_str(), port,
              o.db.c_str(), report.to_version, auth_required ? "required" : "off (loopback)");
  std::fflush(stdout);
  const bool ok = ServeUntilStopped(serving, signals);
  capabilities.scenes.PersistAll();
  Log("stopped; scene models persisted, database closed cleanly");
  return ok ? 0 : 1;
}

// anchordb backup --db FILE [--out FILE | --label ID]: an online copy of the database (the server may be running
// and writing); prints the report as JSON. Bad input: exit 2.
// The audit entry of an admin action taken on the command line (SPEC §8), after the action.
void RecordCliAction(storage::Store& store, const std::string& action, const std::string& map, const json::Json& after) {
  services::AuditEntry entry;
  entry.actor = "cli", entry.action = action, entry.map = map, entry.after_json = after.dump();
  services::AuditService(store).Record(std::move(entry));
}

int BackupCommand(const std::vector<std::string>& args) {
  std::string out, label;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (!TakeOption(args, i, "--out", out) && !TakeOption(args, i, "--label", label)) rest.push_back(args[i]);
  }
  const Config config = LoadConfig(rest, Environment());
  if (!label.empty() && !json::IsValidId(label)) throw std::invalid_argument("--label: not a valid id: " + label);
  RequireExistingDatabase(config.server.db);
  if (out.empty()) {
    const std::int64_t now_ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    out = storage::BackupFileName(BackupDir(config.server), config.server.db, now_ns, label);
  }
  if (std::filesystem::exists(out)) throw std::invalid_argument("--out: " + out + " exists already");
  const storage::BackupReport report = storage::Backup(config.server.db, out, config.server.busy_timeout_ms);
  storage::Store store(StoreOptionsOf(config.server));
  const json::Json document = api::ToJson(report);
  RecordCliAction(store, "backup.create", "", document);
  std::cout << document.dump(1) << "\n";
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
  const storage::StoreOptions options = StoreOptionsOf(config.server);
  storage::Store store(options);  // migrates the file first
  const std::unique_ptr<storage::Connection> owned_connection = storage::OpenConnection(config.server.db, options.connection);
  storage::Connection& connection = *owned_connection;
  const std::int64_t now_ns = request.now_ns.value_or(SystemClock::Instance().NowNs());
  storage::ForgetReport report;
  try {
    report = storage::Forget(connection, map, request.policy, services::ForgetKeepRules(), now_ns, request.dry_run);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kNotFound) throw std::invalid_argument(e.what());
    throw;
  }
  const json::Json document = api::ToJson(report);
  RecordCliAction(store, "map.forget", map, document);
  std::cout << document.dump(1) << "\n";
  return 0;
}

void Usage() {
  std::cout << "usage:\n"
               "  anchordb serve [--config file.json] [--<setting>=<value> ...]\n"
               "  anchordb token create --role reader|writer|admin [--db file]\n"
               "  anchordb forget --db file --map ID [--policy JSON] [--dry-run] [--vacuum]\n"
               "  anchordb backup --db file [--out file | --label ID]\n"
               "  anchordb migrate-to NEW_FILE|postgresql://... --db file|postgresql://...   (copy a whole memory, verified)\n"
               "  anchordb import tum --db file --map ID --dir SEQUENCE [--every N] [--max-frames N] [--camera fr1|fr2|fr3]\n"
               "                      [--fx F --fy F --cx C --cy C] [--depth-scale 5000] [--max-dt 0.02] [--merge]\n"
               "  anchordb import rosbag --db file --map ID --bag FILE.bag [--preset tum] [--depth-topic T] [--info-topic T]\n"
               "                      [--map-frame F] [--every N] [--grid-topic T] [--mask-topic T] [--no-merge]\n"
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
    if (args.size() >= 2 && args[0] == "import" && args[1] == "tum") {
      return ImportTumCommand(std::vector<std::string>(args.begin() + 2, args.end()), Environment());
    }
    if (args[0] == "migrate-to") return MigrateToCommand(std::vector<std::string>(args.begin() + 1, args.end()), Environment());
    if (args.size() >= 2 && args[0] == "import" && args[1] == "rosbag") {
#ifdef ANCHORDB_WITH_ROSBAG
      return ImportRosbagCommand(std::vector<std::string>(args.begin() + 2, args.end()), Environment());
#else
      throw std::invalid_argument("import rosbag is not built in (the ROS 1 packages were missing at build time)");
#endif
    }
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
      storage::Store store(StoreOptionsOf(config.server));
      const CreatedToken t = CreateToken(store, role);
      std::cout << "token " << t.id << " (" << t.role << "): " << t.secret << "\n"
                << "Store it now: only its hash is kept in " << config.server.db << ".\n";
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
