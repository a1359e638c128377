#include "storage/migrations.h"

#include <chrono>
#include <string_view>

#include "schema/error.h"

namespace anchordb::storage {

int UserVersion(Connection& connection) {
  if (connection.engine() == Engine::kPostgresql) {
    {
      Statement exists(connection, "SELECT count(*) FROM pg_tables WHERE schemaname = current_schema() AND "
                                   "tablename = 'schema_migrations'");
      exists.Step();
      if (exists.Int(0) == 0) return 0;  // a new database
    }
    Statement s(connection, "SELECT coalesce(max(version), 0) FROM schema_migrations");
    s.Step();
    return static_cast<int>(s.Int(0));
  }
  Statement s(connection, "PRAGMA user_version");
  s.Step();
  return static_cast<int>(s.Int(0));
}

namespace {
std::int64_t CountOf(Connection& connection, const char* sql) {
  Statement s(connection, sql);
  s.Step();
  return s.Int(0);
}

void RefuseNewer(int version, const std::vector<Migration>& migrations) {
  const int newest = migrations.empty() ? 0 : migrations.back().version;
  if (version > newest) {
    throw Error(ErrorCode::kConflict, "database schema version " + std::to_string(version) +
                                          " is newer than this anchordb build supports (" + std::to_string(newest) +
                                          "); refusing to open it: use a newer anchordb");
  }
}

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void RecordMigration(Connection& connection, const Migration& m) {
  Statement(connection, "INSERT INTO schema_migrations (version, name, applied_ns) VALUES (?, ?, ?)")
      .Bind(1, static_cast<std::int64_t>(m.version))
      .Bind(2, std::string_view(m.name))
      .Bind(3, NowNs())
      .Run();
}

MigrationReport ApplyPostgresMigrations(Connection& connection, const std::vector<Migration>& migrations) {
  MigrationReport report;
  Transaction tx(connection);  // holds the database's writer lock (PostgresConnection::BeginWrite): one migrates
  connection.Exec("CREATE TABLE IF NOT EXISTS schema_migrations (version BIGINT PRIMARY KEY, name TEXT NOT NULL, "
                  "applied_ns BIGINT NOT NULL)");
  report.from_version = UserVersion(connection);
  RefuseNewer(report.from_version, migrations);
  for (const Migration& m : migrations) {
    if (m.version <= report.from_version) continue;
    connection.Exec(m.sql);
    RecordMigration(connection, m);
    report.applied.emplace_back(m.name);
  }
  report.to_version = UserVersion(connection);
  tx.Commit();
  return report;
}
}  // namespace

MigrationReport ApplyMigrations(Connection& connection, const std::vector<Migration>& migrations) {
  if (connection.engine() == Engine::kPostgresql) return ApplyPostgresMigrations(connection, migrations);
  MigrationReport report;
  report.from_version = UserVersion(connection);
  RefuseNewer(report.from_version, migrations);
  connection.Exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL, "
      "applied_ns INTEGER NOT NULL)");
  for (const Migration& m : migrations) {
    if (m.version <= report.from_version) continue;
    // A file that rebuilds a table (SQLite's procedure for schema changes ALTER TABLE cannot make, such as a CHECK
    // constraint) must not let the DROP of the old table cascade into the tables that reference it: it runs with
    // foreign keys off, which SQLite only switches outside a transaction, and the keys are checked before commit.
    const bool foreign_keys_off = std::string_view(m.sql).find(kForeignKeysOffMarker) != std::string_view::npos;
    // Rows whose key has no parent before the file runs (a hand edit, an old bug): the file may not add any.
    std::int64_t orphans_before = 0;
    if (foreign_keys_off) {
      // Inside a transaction the PRAGMA would be ignored without an error, and the rebuild would cascade.
      if (connection.InTransaction()) {
        throw Error(ErrorCode::kInternal, std::string("migration ") + m.name + " needs foreign keys off, but a transaction is open");
      }
      connection.Exec("PRAGMA foreign_keys = OFF");
      if (CountOf(connection, "PRAGMA foreign_keys") != 0) {
        connection.Exec("PRAGMA foreign_keys = ON");
        throw Error(ErrorCode::kInternal, std::string("migration ") + m.name + " needs foreign keys off; SQLite kept them on");
      }
      orphans_before = CountOf(connection, "SELECT count(*) FROM pragma_foreign_key_check");
    }
    struct ForeignKeysBackOn {  // after a failure (the success path switches them on itself, and reports errors)
      Connection& c;
      bool armed;
      ~ForeignKeysBackOn() {
        try {
          if (armed) c.Exec("PRAGMA foreign_keys = ON");
        } catch (...) {  // the migration's own error is the one to report
        }
      }
    } back_on{connection, foreign_keys_off};
    Transaction tx(connection);
    connection.Exec(m.sql);
    if (foreign_keys_off && CountOf(connection, "SELECT count(*) FROM pragma_foreign_key_check") > orphans_before) {
      Statement check(connection, "PRAGMA foreign_key_check");
      check.Step();
      throw Error(ErrorCode::kInternal, std::string("migration ") + m.name + " would leave rows whose foreign key has no "
                                            "parent (table '" + check.Text(0) + "'); nothing was changed");
    }
    RecordMigration(connection, m);
    connection.Exec("PRAGMA user_version = " + std::to_string(m.version));
    tx.Commit();
    if (foreign_keys_off) {
      back_on.armed = false;
      connection.Exec("PRAGMA foreign_keys = ON");
    }
    report.applied.emplace_back(m.name);
  }
  report.to_version = UserVersion(connection);
  return report;
}

}  // namespace anchordb::storage
