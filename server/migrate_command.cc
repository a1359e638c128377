#include "server/migrate_command.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "schema/json_io.h"
#include "server/config.h"
#include "services/audit/audit_service.h"
#include "storage/memory_copy.h"
#include "storage/migrations.h"
#include "storage/store.h"

namespace anchordb::server {

namespace {

// A libpq URI with its password (user:password@) left out, for what is printed and audited.
std::string Printable(const std::string& location) {
  if (!storage::IsPostgresUri(location)) return location;
  const std::size_t scheme = location.find("://") + 3, at = location.find('@', scheme);
  const std::size_t colon = location.find(':', scheme);
  if (at == std::string::npos || colon == std::string::npos || colon > at) return location;
  return location.substr(0, colon) + ":***" + location.substr(at);
}

std::unique_ptr<storage::Connection> OpenMigrated(const std::string& location, const storage::ConnectionOptions& o,
                                                  int& applied) {
  std::unique_ptr<storage::Connection> c = storage::OpenConnection(location, o);
  applied = static_cast<int>(storage::ApplyMigrations(*c, storage::EmbeddedMigrations(c->engine())).applied.size());
  return c;
}

}  // namespace

int MigrateToCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment) {
  std::string target;
  std::vector<std::string> rest;
  for (const std::string& a : args) {
    if (target.empty() && !a.empty() && a[0] != '-' && (rest.empty() || rest.back().rfind("--", 0) != 0 ||
                                                        rest.back().find('=') != std::string::npos)) {
      target = a;
    } else {
      rest.push_back(a);
    }
  }
  if (target.empty()) throw std::invalid_argument("migrate-to needs a target: a new SQLite file or a postgresql:// URI");
  const Config config = LoadConfig(rest, environment);
  const std::string& source = config.server.db;
  if (source == target) throw std::invalid_argument("migrate-to: the target is the source (" + Printable(source) + ")");
  RequireExistingDatabase(source);
  if (!storage::IsPostgresUri(target) && std::filesystem::exists(target)) {
    throw std::invalid_argument("migrate-to: " + target + " exists already; the target must be a new file");
  }
  const storage::StoreOptions options = StoreOptionsOf(config.server);
  int source_applied = 0, target_applied = 0;
  const auto from = OpenMigrated(source, options.connection, source_applied);
  std::unique_ptr<storage::Connection> to;
  try {
    to = OpenMigrated(target, options.connection, target_applied);
  } catch (...) {
    if (!storage::IsPostgresUri(target)) std::filesystem::remove(target);  // the file this command created
    throw;
  }
  const auto start = std::chrono::steady_clock::now();
  storage::CopyReport report;
  try {
    report = storage::CopyMemory(*from, *to, [](const storage::CopyProgress& p) {
      std::fprintf(stderr, "migrate-to: table %d/%d %s: %lld/%lld rows\n", p.table_index, p.tables, p.table.c_str(),
                   static_cast<long long>(p.rows_done), static_cast<long long>(p.rows_total));
    });
  } catch (...) {
    to.reset();
    if (!storage::IsPostgresUri(target)) std::filesystem::remove(target);
    throw;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  json::Json tables = json::Json::array();
  for (const storage::TableCensus& t : report.census) {
    char checksum[17], blobs[17];
    std::snprintf(checksum, sizeof checksum, "%016llx", static_cast<unsigned long long>(t.checksum));
    std::snprintf(blobs, sizeof blobs, "%016llx", static_cast<unsigned long long>(t.blob_checksum));
    tables.push_back({{"table", t.table}, {"rows", t.rows}, {"checksum", checksum}, {"blob_bytes", t.blob_bytes},
                      {"blob_checksum", blobs}});
  }
  const json::Json summary = {{"from", Printable(source)},
                              {"to", Printable(target)},
                              {"schema_version", report.schema_version},
                              {"migrations_applied_to_source", source_applied},
                              {"rows", report.rows},
                              {"blob_bytes", report.blob_bytes},
                              {"verified", true},
                              {"seconds", seconds},
                              {"tables", tables}};
  to.reset();
  // The audit entry goes to the target, after the verified copy (the target holds one audit row more than the source).
  storage::StoreOptions target_options = options;
  target_options.path = target;
  storage::Store store(target_options);
  services::AuditEntry entry;
  entry.actor = "cli", entry.action = "memory.migrate_to";
  json::Json audited = summary;
  audited.erase("tables");
  entry.after_json = audited.dump();
  services::AuditService(store).Record(std::move(entry));
  std::cout << summary.dump(1) << "\n";
  return 0;
}

}  // namespace anchordb::server
