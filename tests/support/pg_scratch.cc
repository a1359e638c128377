#include "tests/support/pg_scratch.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace anchordb::testing {

PgScratch::PgScratch() : dir_(temp_.File("pg")), script_(ANCHORDB_PG_SCRATCH) {
  if (std::system((script_ + " start " + dir_ + " > " + temp_.File("start.log") + " 2>&1").c_str()) != 0) {
    std::ifstream log(temp_.File("start.log"));
    throw std::runtime_error("pg-scratch start failed: " + std::string(std::istreambuf_iterator<char>(log), {}));
  }
  std::ifstream env(dir_ + "/pg.env");
  for (std::string line; std::getline(env, line);) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) env_[line.substr(0, eq)] = line.substr(eq + 1);
  }
}

PgScratch::~PgScratch() { std::system((script_ + " stop " + dir_ + " > /dev/null 2>&1").c_str()); }

std::string PgScratch::Uri(const std::string& database) const {
  return "postgresql://postgres@127.0.0.1:" + env_.at("PGPORT") + "/" + database + "?sslmode=disable&gssencmode=disable";
}

int PgScratch::PgCtl(const std::string& args) const {
  const std::string as = getuid() == 0 ? "runuser -u postgres -- " : "";
  return std::system((as + "/usr/lib/postgresql/15/bin/pg_ctl -D " + dir_ + "/data -l " + dir_ +
                      "/data/server.log -w -t 60 " + args + " > /dev/null 2>&1").c_str());
}

std::string PgScratch::StartOptions() const {
  return "-o \"-p " + env_.at("PGPORT") + " -k " + env_.at("PGHOST") + " -c listen_addresses=127.0.0.1 -c max_connections=200\"";
}

PgScratch& SharedPgScratch() {
  static std::unique_ptr<PgScratch> server = std::make_unique<PgScratch>();  // destroyed (stopped) at exit
  return *server;
}

namespace {
void AdminExec(const std::string& sql) {
  auto admin = storage::OpenConnection(SharedPgScratch().Uri("postgres"), {});
  admin->Exec(sql);
}
}  // namespace

TestDatabase::TestDatabase(storage::Engine engine) : engine_(engine) {
  if (engine_ == storage::Engine::kSqlite) {
    location_ = dir_.File("memory.sqlite");
    return;
  }
  static std::atomic<int> counter{0};
  pg_database_ = "test_" + std::to_string(getpid()) + "_" + std::to_string(++counter);
  AdminExec("CREATE DATABASE " + pg_database_);
  location_ = SharedPgScratch().Uri(pg_database_);
}

TestDatabase::~TestDatabase() {
  if (pg_database_.empty()) return;
  try {
    AdminExec("DROP DATABASE IF EXISTS " + pg_database_ + " WITH (FORCE)");
  } catch (...) {  // the server goes with the process anyway
  }
}

std::string EngineName(const ::testing::TestParamInfo<storage::Engine>& info) {
  return info.param == storage::Engine::kPostgresql ? "PostgreSQL" : "SQLite";
}

}  // namespace anchordb::testing
