#include "tests/support/server_process.h"

#include <signal.h>
#include <sys/wait.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>

#include "tests/support/pg_scratch.h"

namespace anchordb::testing {

std::string AnchordbBin() {
  const char* bin = std::getenv("ANCHORDB_BIN");
  return bin && *bin ? bin : ANCHORDB_BUILT_BIN;
}

std::string DatabaseLocation(const std::string& db_path) {
  const char* engine = std::getenv("ANCHORDB_TEST_ENGINE");
  if (!engine || std::string(engine) != "postgresql" || storage::IsPostgresUri(db_path)) return db_path;
  static std::mutex mutex;
  static std::map<std::string, std::string> databases;
  std::lock_guard lock(mutex);
  auto it = databases.find(db_path);
  if (it == databases.end()) {
    const std::string name = "http_" + std::to_string(getpid()) + "_" + std::to_string(databases.size() + 1);
    storage::OpenConnection(SharedPgScratch().Uri("postgres"), {})->Exec("CREATE DATABASE " + name);
    it = databases.emplace(db_path, SharedPgScratch().Uri(name)).first;
  }
  return it->second;
}

ServerProcess::ServerProcess(const std::string& db_path, std::vector<std::string> extra_args) {
  const std::string bin = AnchordbBin();
  std::vector<std::string> args = {bin, "serve", "--db", DatabaseLocation(db_path), "--port", "0", "--log_requests=false"};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("pipe failed");
  const pid_t test_pid = getpid();
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    // The server dies with the test (a test that aborts, e.g. on a sanitizer report, runs no destructor): an orphaned
    // server would hold ctest's output pipe open and stall the run until its timeout. (Tests start servers from the
    // thread that lives as long as the test.)
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != test_pid) _exit(127);  // the test ended before prctl
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    close(out[1]);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out[1]);
  FILE* f = fdopen(out[0], "r");
  char line[512] = {0};
  if (!std::fgets(line, sizeof(line), f)) {
    std::fclose(f);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    throw std::runtime_error("anchordb exited before listening (status " + std::to_string(status) + ")");
  }
  std::fclose(f);  // the server writes nothing more to stdout
  const std::string text(line);
  const auto colon = text.find(':', text.find("127.0.0.1"));
  if (colon == std::string::npos) throw std::runtime_error("unexpected first line: " + text);
  port_ = std::atoi(text.c_str() + colon + 1);
}

ServerProcess::~ServerProcess() {
  if (pid_ > 0) Kill();
}

int ServerProcess::Stop() {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return status;
}

void ServerProcess::Kill() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

}  // namespace anchordb::testing
