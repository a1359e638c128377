#include "storage/migrations.h"

#include <chrono>

#include "schema/error.h"

namespace anchordb::storage {

int UserVersion(Connection& connection) {
  Statement s(connection, "PRAGMA user_version");
  s.Step();
  return static_cast<int>(s.Int(0));
}

MigrationReport ApplyMigrations(Connection& connection, const std::vector<Migration>& migrations) {
  MigrationReport report;
  report.from_version = UserVersion(connection);
  const int newest = migrations.empty() ? 0 : migrations.back().version;
  if (report.from_version > newest) {
    throw Error(ErrorCode::kConflict, "database schema version " + std::to_string(report.from_version) +
                                          " is newer than this anchordb build supports (" + std::to_string(newest) +
                                          "); refusing to open it: use a newer anchordb");
  }
  connection.Exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL, "
      "applied_ns INTEGER NOT NULL)");
  for (const Migration& m : migrations) {
    if (m.version <= report.from_version) continue;
    Transaction tx(connection);
    connection.Exec(m.sql);
    const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::system_clock::now().time_since_epoch()).count();
    Statement(connection, "INSERT INTO schema_migrations (version, name, applied_ns) VALUES (?, ?, ?)")
        .Bind(1, static_cast<std::int64_t>(m.version))
        .Bind(2, std::string_view(m.name))
        .Bind(3, static_cast<std::int64_t>(now_ns))
        .Run();
    connection.Exec("PRAGMA user_version = " + std::to_string(m.version));
    tx.Commit();
    report.applied.emplace_back(m.name);
  }
  report.to_version = UserVersion(connection);
  return report;
}

}  // namespace anchordb::storage
