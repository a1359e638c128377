#pragma once
// `anchordb migrate-to TARGET --db SOURCE`: copies a whole memory from one database into a new one, of either engine
// (a robot's SQLite file into a site's PostgreSQL database, and back): storage/memory_copy.h, verified by row counts
// and checksums of every value and blob before it commits. Progress lines on stderr, the report as JSON on stdout.
#include <map>
#include <string>
#include <vector>

namespace anchordb::server {

// Bad input (no target, a SQLite target that exists, a source that does not): std::invalid_argument.
int MigrateToCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment);

}  // namespace anchordb::server
