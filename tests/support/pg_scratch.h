#pragma once
// PostgreSQL for tests (issue 30): a throwaway server started by scripts/pg-scratch on a free loopback port in a
// temporary folder (stopped by its PID and removed at the end), and a database per test on either engine.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "storage/connection.h"
#include "tests/support/temp_dir.h"

namespace anchordb::testing {

class PgScratch {
 public:
  PgScratch();
  ~PgScratch();
  PgScratch(const PgScratch&) = delete;
  PgScratch& operator=(const PgScratch&) = delete;

  // A URI of database `database` on this server (no TLS or GSSAPI negotiation: the scratch server offers neither).
  std::string Uri(const std::string& database = "anchordb") const;
  // pg_ctl on this server's data folder as the user the server runs as, e.g. "stop -m immediate"; answers its status.
  int PgCtl(const std::string& args) const;
  // The options `pg_ctl start -o ...` needs to bring this server back on its port and socket folder.
  std::string StartOptions() const;

 private:
  TempDir temp_;
  std::string dir_;
  std::string script_;
  std::map<std::string, std::string> env_;
};

// One server per test process, started at the first use and stopped at exit.
PgScratch& SharedPgScratch();

// A database for one test: a file in a temporary folder (SQLite) or a new database on the shared scratch server
// (PostgreSQL), dropped at the end (declare it before anything that holds connections to it).
class TestDatabase {
 public:
  explicit TestDatabase(storage::Engine engine);
  ~TestDatabase();
  TestDatabase(const TestDatabase&) = delete;
  TestDatabase& operator=(const TestDatabase&) = delete;

  storage::Engine engine() const { return engine_; }
  const std::string& location() const { return location_; }

 private:
  storage::Engine engine_;
  TempDir dir_;
  std::string location_;
  std::string pg_database_;
};

// For INSTANTIATE_TEST_SUITE_P(Engines, Suite, BothEngines(), EngineName).
inline auto BothEngines() { return ::testing::Values(storage::Engine::kSqlite, storage::Engine::kPostgresql); }
std::string EngineName(const ::testing::TestParamInfo<storage::Engine>& info);

}  // namespace anchordb::testing
