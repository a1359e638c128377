#include "server/config.h"

#include <cmath>
#include <variant>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace anchordb::server {
namespace {

void BindServerSettings(SettingsBinder& b, ServerOptions& o) {
  b.Bind("db", "SQLite database file (created and migrated at start-up)", &o.db);
  b.Bind("backup_dir", "directory of the online backups (POST /v1/backups); empty: 'backups' beside the database",
         &o.backup_dir);
  b.Bind("bind", "address to listen on; any non-loopback address requires API tokens", &o.bind);
  b.Bind("port", "TCP port (0 = any free port, printed at start-up)", &o.port, 0, 65535);
  b.Bind("threads", "HTTP worker threads: requests served at once. A worker serves one request, not a connection: "
                    "idle keep-alive connections hold none", &o.threads, 1, 1024);
  b.Bind("max_connections", "client connections open at once; one more closes the longest-idle keep-alive connection, "
                            "or, if none is idle, is answered 503 with Retry-After and closed", &o.max_connections, 1, 100000);
  b.Bind("max_queued_requests", "complete requests waiting for a worker; one more is answered 503 with Retry-After "
                                "(and its connection closed)", &o.max_queued_requests, 1, 1000000);
  b.Bind("idle_timeout_s", "an idle keep-alive connection is closed after this long [s]", &o.idle_timeout_s, 1, 86400);
  b.Bind("auth", "auto (open on loopback, tokens required elsewhere), required, or off (loopback only)", &o.auth);
  b.Require([&o] { return o.auth == "auto" || o.auth == "required" || o.auth == "off"; }, "auth must be auto, required or off");
  b.Bind("synchronous", "SQLite synchronous mode: FULL (fsync every commit) or NORMAL", &o.synchronous);
  b.Require([&o] { return o.synchronous == "FULL" || o.synchronous == "NORMAL"; }, "synchronous must be FULL or NORMAL");
  b.Bind("busy_timeout_ms", "how long SQLite waits for a lock before giving up [ms]", &o.busy_timeout_ms, 0, 600000);
  b.Bind("reader_connections", "read-only SQLite connections in the pool", &o.reader_connections, 1, 64);
  b.Bind("max_body_bytes", "largest accepted request body [bytes]", &o.max_body_bytes, 1024, 4e9);
  b.Bind("max_pending_writes", "write requests (writer or admin routes) in service at once; one more is answered 503 "
                               "with Retry-After at once. Below `threads` (default 24 of 32), so that reads always find "
                               "a worker while writes wait for the database writer", &o.max_pending_writes, 1, 1e6);
  b.Bind("log_requests", "log one line per request to stderr", &o.log_requests);
  b.Bind("malloc_arenas", "glibc malloc arenas of the server (0: twice the cores, at least 4); fewer arenas keep the "
                          "resident memory of a long run flat", &o.malloc_arenas, 0, 1024);
  b.Bind("grounding_knowledge", "JSON file {categories, frame_prior} replacing the built-in grounding tables "
                                "(engine/grounding/*.json); empty = built in", &o.grounding_knowledge);
}

nlohmann::json ToJson(const SettingValue& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x); }, v);
}

}  // namespace

SettingsBinder BindSettings(Config& c) {
  SettingsBinder b;
  BindServerSettings(b, c.server);
  services::BindCapabilitySettings(b, c.capabilities);
  return b;
}

bool IsLoopback(const std::string& bind) {
  return bind == "localhost" || bind == "::1" || bind.rfind("127.", 0) == 0;
}

Config LoadConfig(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment) {
  Config config;
  const SettingsBinder bindings = BindSettings(config);
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
      const SettingsBinder::Entry* b = bindings.Find(key);
      if (!b) throw std::invalid_argument("config file " + value + ": unknown setting '" + key + "'");
      b->set(v.is_string() ? v.get<std::string>() : v.dump());
    }
  }
  for (const SettingsBinder::Entry& b : bindings.entries()) {
    std::string env_name = "ANCHORDB_";
    for (char c : b.info.name) env_name += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (auto it = environment.find(env_name); it != environment.end()) b.set(it->second);
  }
  for (const auto& [name, value] : flags) {
    if (name == "config") continue;
    const SettingsBinder::Entry* b = bindings.Find(name);
    if (!b) throw std::invalid_argument("unknown flag --" + name + " (see --help)");
    b->set(value);
  }
  bindings.Validate();
  return config;
}

nlohmann::json SettingsJson(const Config& config) {
  Config copy = config;
  const SettingsBinder bindings = BindSettings(copy);
  nlohmann::json out = {{"settings", nlohmann::json::array()}};
  for (const SettingsBinder::Entry& b : bindings.entries()) {
    nlohmann::json s = {{"name", b.info.name}, {"type", b.info.type}, {"description", b.info.description},
                        {"value", ToJson(b.get())}};
    if (std::isfinite(b.info.min)) s["min"] = b.info.min;
    if (std::isfinite(b.info.max)) s["max"] = b.info.max;
    out["settings"].push_back(std::move(s));
  }
  return out;
}

std::string SettingsHelp() {
  Config defaults;
  const SettingsBinder bindings = BindSettings(defaults);
  std::string out;
  for (const SettingsBinder::Entry& b : bindings.entries()) {
    std::string bounds;
    if (std::isfinite(b.info.min) || std::isfinite(b.info.max)) {
      bounds = ", in [" + FormatBound(b.info.min) + ", " + FormatBound(b.info.max) + "]";
    }
    out += "  --" + b.info.name + "=<" + b.info.type + ">  " + b.info.description + " (default " + ToJson(b.get()).dump() +
           bounds + ")\n";
  }
  return out;
}

storage::StoreOptions StoreOptionsOf(const ServerOptions& c) {
  storage::StoreOptions o;
  o.path = c.db;
  o.connection.busy_timeout_ms = c.busy_timeout_ms;
  o.connection.synchronous = c.synchronous;
  o.reader_connections = c.reader_connections;
  return o;
}

void RequireExistingDatabase(const std::string& location) {
  if (!storage::IsPostgresUri(location) && !std::filesystem::exists(location)) {
    throw std::invalid_argument("no database at " + location);
  }
}

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

}  // namespace anchordb::server
