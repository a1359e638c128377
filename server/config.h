#pragma once
// The server's typed configuration: the server's own options and the options structs of every capability, each
// default in its struct. Values are loaded, in increasing precedence, from an optional JSON file (--config),
// environment variables ANCHORDB_<NAME> and command-line flags --name=value. Unknown keys in the file and unknown
// flags are errors. Every setting is bound once (BindSettings: the server's below, each capability's in
// services/<capability>/*_settings.cc) and `--help` and GET /v1/settings are generated from those bindings.
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "schema/settings.h"
#include "services/capabilities.h"
#include "storage/store.h"

namespace anchordb::server {

struct ServerOptions {
  std::string db = "./var/anchordb.sqlite";
  std::string backup_dir;  // empty: "backups" beside the database file
  std::string bind = "127.0.0.1";
  int port = 8765;
  // Serving limits (server/http_serving.h). max_pending_writes < threads, so that writes (which wait for the one
  // SQLite writer) never take more than 3/4 of the workers and reads always find one.
  int threads = 32;
  int max_connections = 512;
  int max_queued_requests = 512;
  int idle_timeout_s = 60;
  std::string auth = "auto";
  std::string synchronous = "FULL";
  int busy_timeout_ms = 5000;
  int reader_connections = 4;
  std::int64_t max_body_bytes = 64ll << 20;
  int max_pending_writes = 24;
  bool log_requests = true;
  std::string grounding_knowledge;  // file replacing the built-in grounding tables; empty = built in
  // glibc malloc arenas of the server process; 0: twice the cores, at least 4 (glibc's own default is 8 per core, and
  // under many threads each arena keeps its own high-water mark, so resident memory creeps up for minutes).
  int malloc_arenas = 0;
};

struct Config {
  ServerOptions server;
  services::CapabilityOptions capabilities;
};

// Binds every setting of `config` (which must outlive the binder), in a stable order.
SettingsBinder BindSettings(Config& config);

// Loads a configuration from `args` (flags after the subcommand), the environment and the file named by
// --config. Throws std::invalid_argument with a message naming the bad key or value.
Config LoadConfig(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment);

// {"settings":[{"name","type","description","value","min"?,"max"?}]}
nlohmann::json SettingsJson(const Config& config);

// Text for --help: every setting with its type, description, bounds and default.
std::string SettingsHelp();

bool IsLoopback(const std::string& bind);

// The store options of the server's settings (path, busy timeout, synchronous, reader connections).
storage::StoreOptions StoreOptionsOf(const ServerOptions& c);

// A subcommand's own option `name` at args[i], as "--name VALUE" (i moves past the value) or "--name=VALUE".
// Throws std::invalid_argument when the value is missing.
bool TakeOption(const std::vector<std::string>& args, std::size_t& i, const std::string& name, std::string& value);

// A subcommand's --db must name a database that exists: a SQLite file that is there (a PostgreSQL URI is checked by
// connecting). Throws std::invalid_argument("no database at ...") otherwise.
void RequireExistingDatabase(const std::string& location);

}  // namespace anchordb::server
