#pragma once
// The PostgreSQL engine of the storage contract (storage/connection.h), over libpq. SQL is written once for both
// engines: `?` and `?N` placeholders become `$k`, parameters are sent typed (int8, float8, text, bytea binary) and
// rows are read in text form. Error kinds by SQLSTATE, as SQLite's: 23505 / 23503 (unique, foreign key) kConflict;
// 23514 / 23502 (CHECK, NOT NULL) kInternal; 40001 / 40P01 / 57014 (serialisation failure, deadlock, statement
// timeout or cancel) kOverloaded; 53100 (disk full) kInsufficientStorage; a lost connection (class 08, 57P0x), a
// read-only standby (25006) or too many connections (53300) kUnavailable, and the next call reconnects.
#include <libpq-fe.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "storage/connection.h"

namespace anchordb::storage {

// `?` and `?N` placeholders outside quoted literals become `$k`; answers the text and the number of parameters.
std::pair<std::string, int> PostgresPlaceholders(std::string_view sql);

class PostgresConnection final : public Connection {
 public:
  PostgresConnection(const std::string& uri, const ConnectionOptions& options);
  ~PostgresConnection() override;

  Engine engine() const override { return Engine::kPostgresql; }
  void Exec(std::string_view sql) override;
  std::int64_t Changes() const override { return changes_; }
  bool InTransaction() const override;
  void EndStuckTransaction() override;
  void Interrupt() override;
  // A write transaction takes the database's writer lock first (a transaction-scoped advisory lock, released by
  // the commit or rollback, or by the server when the session dies), as SQLite's BEGIN IMMEDIATE does: writers
  // (the store's, a job's own connection, another server) are serialised, so read-then-write rules hold and ids
  // commit in the order they were given (an event stream's Last-Event-ID never skips a late commit). Waiting longer
  // than busy_timeout_ms fails as kOverloaded.
  void BeginWrite() override;
  // A read transaction costs no round trip of its own: BEGIN is sent in one pipeline with the first statement
  // (libpq's pipeline mode), and the ROLLBACK that ends it is sent without waiting; its answer is read before the
  // connection's next use. A read that ran no statement sends nothing.
  // kOneStatement begins nothing: the statement runs alone in autocommit (READ COMMITTED: one snapshot).
  void BeginRead(ReadScope scope) override;
  void EndRead() override;

  // For the cursors of this connection: runs a prepared statement (preparing it once per SQL text and parameter
  // types) and answers its result; throws the mapped error.
  PGresult* Run(const std::string& sql, int parameters, const Oid* types, const char* const* values,
                const int* lengths, const int* formats) const;

 private:
  std::unique_ptr<Cursor> Acquire(std::string_view sql) const override;
  void Release(std::unique_ptr<Cursor> cursor) const override;
  // Reconnects a connection found broken (a restarted or failed-over server); throws kUnavailable when it cannot.
  void EnsureConnected() const;
  PGresult* RunOnce(const std::string& sql, int parameters, const Oid* types, const char* const* values,
                    const int* lengths, const int* formats) const;
  // Reads and drops the results of a pipeline up to and including its sync.
  void ReadThroughSync() const;
  // Reads the answers of a command sent without waiting (EndRead's ROLLBACK) and leaves pipeline mode.
  void Drain() const;
  // Sends the deferred BEGIN of a read transaction, alone (before an Exec).
  void SendPendingBegin() const;
  // Runs a prepared statement after the deferred BEGIN, both in one pipeline.
  PGresult* ExecPreparedAfterBegin(const std::string& name, int parameters, const char* const* values,
                                   const int* lengths, const int* formats) const;
  [[noreturn]] void ThrowResult(PGresult* result, std::string_view what) const;

  std::string uri_;
  ConnectionOptions options_;
  mutable PGconn* conn_ = nullptr;
  mutable std::mutex cancel_mutex_;  // Interrupt runs on another thread
  mutable PGcancel* cancel_ = nullptr;
  mutable std::int64_t changes_ = 0;
  mutable std::map<std::string, std::string> prepared_;  // SQL + parameter types -> prepared statement name
  mutable std::string pending_begin_;   // a read transaction's BEGIN, not yet sent
  bool one_statement_read_ = false;     // inside a kOneStatement read (its statement may run again on a new session)
  mutable bool pending_results_ = false;  // a command was sent in pipeline mode and its answers are not read yet
};

}  // namespace anchordb::storage
