#pragma once
// Thin RAII wrappers over the SQLite C API. Every failure throws anchordb::Error with SQLite's message: kConflict for
// constraint violations (unique, primary key, foreign key; a CHECK or NOT NULL violation is kInternal), kOverloaded when the busy timeout ran out, kInsufficientStorage when the disk is full,
// kUnavailable for I/O errors and out of memory (the statement had no effect; retrying later may succeed), else
// kInternal.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "schema/error.h"

namespace anchordb::storage {

struct ConnectionOptions {
  int busy_timeout_ms = 5000;
  // FULL: every commit is fsynced before it is acknowledged (durable across power loss); NORMAL is only
  // durable across process crashes in WAL mode.
  std::string synchronous = "FULL";
  bool read_only = false;
  // The SQLite VFS to open the file with; empty: the process default (the unix VFS unless a test replaced it).
  std::string vfs;
};

class Connection {
 public:
  Connection(const std::string& path, const ConnectionOptions& options);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  sqlite3* handle() const { return db_; }
  void Exec(std::string_view sql);
  std::int64_t Changes() const { return sqlite3_changes64(db_); }
  // Rolls back a transaction left open (a failed statement whose ROLLBACK failed as well); no-op in autocommit.
  void EndStuckTransaction();

 private:
  friend class Statement;
  // Prepared statements are kept per connection, one per SQL text, and reused: preparing (parsing, planning) was
  // the largest cost of short read queries. A connection is used by one thread at a time (Store leases it).
  sqlite3_stmt* TakeCached(std::string_view sql) const;
  void ReturnToCache(sqlite3_stmt* stmt) const;

  sqlite3* db_ = nullptr;
  mutable std::unordered_map<std::string, sqlite3_stmt*> statement_cache_;
};

class Statement {
 public:
  Statement(const Connection& connection, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Bind by 1-based position; return *this for chaining.
  Statement& Bind(int index, std::int64_t value);
  Statement& Bind(int index, double value);
  Statement& Bind(int index, std::string_view text);
  Statement& BindBlob(int index, std::string_view bytes);
  Statement& BindNull(int index);

  // Advances to the next row; false when done.
  bool Step();
  // Runs a statement that returns no rows.
  void Run();

  std::int64_t Int(int column) const { return sqlite3_column_int64(stmt_, column); }
  double Double(int column) const { return sqlite3_column_double(stmt_, column); }
  std::string Text(int column) const;
  std::string Blob(int column) const;
  bool IsNull(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

 private:
  const Connection& connection_;
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE ... COMMIT; rolls back in the destructor unless Commit() ran.
class Transaction {
 public:
  explicit Transaction(Connection& connection);
  ~Transaction();
  void Commit();

 private:
  Connection& connection_;
  bool done_ = false;
};

// BEGIN (deferred) ... end: the statements run inside share one read snapshot (a consistent answer across several
// queries) and one set of file locks instead of one per statement. Ends in the destructor; nothing to commit.
class ReadTransaction {
 public:
  explicit ReadTransaction(Connection& connection);
  ~ReadTransaction();
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;

 private:
  Connection& connection_;
};

// NULL for nullopt, and back.
inline void BindOptional(Statement& s, int index, const std::optional<std::int64_t>& v) {
  if (v) s.Bind(index, *v);
  else s.BindNull(index);
}
inline std::optional<std::int64_t> OptionalInt(const Statement& s, int column) {
  if (s.IsNull(column)) return std::nullopt;
  return s.Int(column);
}

[[noreturn]] void ThrowSqliteError(sqlite3* db, int rc, std::string_view what);

// The error kind of a SQLite result code (see the header comment).
ErrorCode ErrorCodeOfSqlite(int rc);

}  // namespace anchordb::storage
