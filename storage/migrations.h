#pragma once
// The migration runner: brings a database to the newest schema version embedded in this binary.
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct Migration {
  int version;       // NNNN of the file name
  const char* name;  // file name
  const char* sql;
};

// The files of migrations/<engine>/, embedded at build time, in version order.
const std::vector<Migration>& EmbeddedMigrations(Engine engine);

struct MigrationReport {
  int from_version = 0;
  int to_version = 0;
  std::vector<std::string> applied;  // file names applied now
};

// A migration whose SQL contains this line runs with foreign keys off (a table rebuild; see ApplyMigrations).
inline constexpr const char* kForeignKeysOffMarker = "-- anchordb: foreign_keys off";

// PostgreSQL: every migration newer than the newest row of `schema_migrations` is applied in one transaction that
// holds an advisory lock first (servers starting together migrate once, the others wait and find nothing to do);
// PostgreSQL's DDL is transactional, so a failing file leaves the database as it was. A newer database is refused.
// SQLite: applies every migration newer than the database's `PRAGMA user_version`, each in its own transaction,
// recording it in `schema_migrations`. A migration marked with kForeignKeysOffMarker runs with foreign keys off
// (so that dropping a table it rebuilds does not cascade) and fails, changing nothing, when `PRAGMA
// foreign_key_check` finds more violations before its commit than before it ran (rows orphaned earlier do not block
// start-up); foreign keys are on again afterwards either way. A database whose version is newer than the newest known migration is
// refused (Error kConflict) with a message naming both versions; nothing is changed then.
MigrationReport ApplyMigrations(Connection& connection, const std::vector<Migration>& migrations);

// The schema version of the database: SQLite's `PRAGMA user_version`, PostgreSQL's newest `schema_migrations` row
// (0 for an empty database).
int UserVersion(Connection& connection);

}  // namespace anchordb::storage
