#pragma once
// The migration runner: brings a database to the newest schema version embedded in this binary.
#include <string>
#include <vector>

#include "storage/sqlite.h"

namespace anchordb::storage {

struct Migration {
  int version;       // NNNN of the file name
  const char* name;  // file name
  const char* sql;
};

// The files of migrations/, embedded at build time, in version order.
const std::vector<Migration>& EmbeddedMigrations();

struct MigrationReport {
  int from_version = 0;
  int to_version = 0;
  std::vector<std::string> applied;  // file names applied now
};

// Applies every migration newer than the database's `PRAGMA user_version`, each in its own transaction,
// recording it in `schema_migrations`. A database whose version is newer than the newest known migration is
// refused (Error kConflict) with a message naming both versions; nothing is changed then.
MigrationReport ApplyMigrations(Connection& connection, const std::vector<Migration>& migrations);

int UserVersion(Connection& connection);

}  // namespace anchordb::storage
