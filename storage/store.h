#pragma once
// The store over either engine (a SQLite file path or a PostgreSQL URI, storage/connection.h): one writer
// connection (writes are serialised and each runs in one write transaction that is committed before the call
// returns) and a pool of reader connections (SQLite's WAL or PostgreSQL's MVCC lets them read while a write is in
// progress). Opening migrates the database to the newest schema of its engine (migrations/<engine>/).
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "storage/migrations.h"
#include "storage/connection.h"

namespace anchordb::storage {

// A function the calling thread arms to run inside its next write transaction, just before the commit (the audit
// trail writes an operator's entry in the change's own transaction: services/audit/). It runs at most once; an
// exception from it rolls the transaction back. An empty function disarms it.
void SetBeforeCommitHook(std::function<void(Connection&)> hook);
void RunBeforeCommitHook(Connection& connection);  // by Store::Write

struct StoreOptions {
  std::string path;
  ConnectionOptions connection;
  int reader_connections = 4;
};

class Store {
 public:
  explicit Store(const StoreOptions& options);
  ~Store();

  // Runs `fn` on a reader connection (blocks while all readers are leased) inside one read transaction: every
  // query of `fn` sees the same snapshot.
  template <typename F>
  auto Read(F&& fn) {
    Lease lease(*this);
    ReadTransaction snapshot(*lease.connection);
    return fn(*lease.connection);
  }

  // Runs `fn`, which runs exactly one statement, on a reader connection with no transaction around it (the
  // statement is consistent on its own; PostgreSQL is spared a BEGIN and a ROLLBACK). A second statement in `fn`
  // fails with kInternal: use Read for anything more.
  template <typename F>
  auto ReadOneStatement(F&& fn) {
    Lease lease(*this);
    ReadTransaction one(*lease.connection, ReadScope::kOneStatement);
    return fn(*lease.connection);
  }

  // Runs `fn` inside a write transaction on the writer connection and commits; an exception rolls back (nothing of
  // `fn` stays written). A writer connection left inside a transaction by a failure is replaced before the next write.
  template <typename F>
  auto Write(F&& fn) {
    std::lock_guard<std::mutex> lock(write_mutex_);
    Connection& writer = UsableWriter();
    Transaction tx(writer);
    if constexpr (std::is_void_v<decltype(fn(writer))>) {
      fn(writer);
      RunBeforeCommitHook(writer);
      tx.Commit();
    } else {
      auto result = fn(writer);
      RunBeforeCommitHook(writer);
      tx.Commit();
      return result;
    }
  }

  const MigrationReport& migration_report() const { return migration_report_; }
  const std::string& path() const { return options_.path; }
  // PRAGMA integrity_check on the writer connection; "ok" when the file is sound.
  std::string IntegrityCheck();

 private:
  class Lease {
   public:
    explicit Lease(Store& store);
    ~Lease();
    Connection* connection;

   private:
    Store& store_;
  };

  // The writer, after ending a stuck transaction; reopened when it cannot be ended. Called under write_mutex_.
  Connection& UsableWriter();

  StoreOptions options_;
  std::unique_ptr<Connection> writer_;
  std::mutex write_mutex_;
  std::vector<std::unique_ptr<Connection>> readers_;
  std::vector<Connection*> idle_readers_;
  std::mutex reader_mutex_;
  std::condition_variable reader_available_;
  MigrationReport migration_report_;
};

}  // namespace anchordb::storage
