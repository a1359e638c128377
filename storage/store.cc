#include "storage/store.h"

#include "schema/error.h"

namespace anchordb::storage {

namespace {
thread_local std::function<void(Connection&)> t_before_commit;
}  // namespace

void SetBeforeCommitHook(std::function<void(Connection&)> hook) { t_before_commit = std::move(hook); }

void RunBeforeCommitHook(Connection& connection) {
  if (!t_before_commit) return;
  auto hook = std::move(t_before_commit);
  t_before_commit = nullptr;
  hook(connection);
}

Store::Store(const StoreOptions& options) : options_(options) {
  writer_ = OpenConnection(options_.path, options_.connection);
  migration_report_ = ApplyMigrations(*writer_, EmbeddedMigrations(writer_->engine()));
  ConnectionOptions reader_options = options_.connection;
  reader_options.read_only = true;
  for (int i = 0; i < std::max(1, options_.reader_connections); ++i) {
    readers_.push_back(OpenConnection(options_.path, reader_options));
    idle_readers_.push_back(readers_.back().get());
  }
}

Store::~Store() {
  readers_.clear();
  // A clean close checkpoints the WAL into the main file.
  writer_.reset();
}

Connection& Store::UsableWriter() {
  writer_->EndStuckTransaction();
  if (writer_->InTransaction()) {
    writer_ = OpenConnection(options_.path, options_.connection);  // throws: the old one is kept
  }
  return *writer_;
}

std::string Store::IntegrityCheck() {
  std::lock_guard<std::mutex> lock(write_mutex_);
  if (writer_->engine() == Engine::kPostgresql) {
    // The server checks its own pages (checksums, WAL); here only that the schema answers.
    Statement s(*writer_, "SELECT count(*) FROM schema_migrations");
    s.Step();
    return "ok";
  }
  Statement s(*writer_, "PRAGMA integrity_check");
  std::string result;
  while (s.Step()) result += (result.empty() ? "" : "; ") + s.Text(0);
  return result;
}

Store::Lease::Lease(Store& store) : store_(store) {
  std::unique_lock<std::mutex> lock(store_.reader_mutex_);
  store_.reader_available_.wait(lock, [&] { return !store_.idle_readers_.empty(); });
  connection = store_.idle_readers_.back();
  store_.idle_readers_.pop_back();
}

Store::Lease::~Lease() {
  {
    std::lock_guard<std::mutex> lock(store_.reader_mutex_);
    store_.idle_readers_.push_back(connection);
  }
  store_.reader_available_.notify_one();
}

}  // namespace anchordb::storage
