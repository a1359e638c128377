#pragma once
// Starts the real `anchordb serve` binary on loopback (port 0) for HTTP tests and stops it: SIGTERM (graceful),
// or SIGKILL (crash). The binary comes from $ANCHORDB_BIN. With ANCHORDB_TEST_ENGINE=postgresql the server runs on a
// database of a scratch PostgreSQL (tests/support/pg_scratch.h) instead of the SQLite file the test names.
#include <string>
#include <vector>

namespace anchordb::testing {

// The anchordb binary the tests run: $ANCHORDB_BIN, else the one this build made.
std::string AnchordbBin();

// The location a server and the CLI should open for the database file a test names: the path itself, or with
// ANCHORDB_TEST_ENGINE=postgresql a database of its own on the process's scratch PostgreSQL (the same path again,
// e.g. after a restart, gives the same database). Quote it on a shell command line (a URI holds '&').
std::string DatabaseLocation(const std::string& db_path);

class ServerProcess {
 public:
  // Starts `anchordb serve --db <db> --port 0 --log_requests=false <extra...>` and waits for its listening line.
  ServerProcess(const std::string& db_path, std::vector<std::string> extra_args = {});
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  // Graceful stop; returns the exit status.
  int Stop();
  // kill -9.
  void Kill();

 private:
  int pid_ = -1;
  int port_ = 0;
};

}  // namespace anchordb::testing
