#pragma once
// The storage contract's connection seam: a connection to one database and the prepared statements run on it, with
// no database engine's type in sight. Repositories and services speak to `Connection` and `Statement` only; the
// engines implement `Connection` and `Cursor` (SQLite: storage/sqlite.h, the only header that includes sqlite3.h).
// Every failure throws anchordb::Error mapped by the engine to the same kinds: kConflict for a unique, primary key or
// foreign key violation, kInternal for a CHECK or NOT NULL violation (a row our code built wrong), kOverloaded when
// a lock wait ran out, kInsufficientStorage for a full disk, kUnavailable when the database cannot be reached or
// read for now (retrying later may succeed; nothing of the failed statement stayed).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "schema/error.h"

namespace anchordb::storage {

enum class Engine { kSqlite, kPostgresql };

// What a read transaction promises. kSnapshot: several statements that must see one snapshot (a transaction is
// begun). kOneStatement: exactly one statement, consistent on its own, so no transaction is begun at all (on
// PostgreSQL that saves the BEGIN and the ROLLBACK, two of the three messages of a one-query read); a second
// statement in such a read is a programming error (kInternal), found by the first test that runs it.
enum class ReadScope { kSnapshot, kOneStatement };

// Settings of one connection. `busy_timeout_ms`, `synchronous` and `vfs` are SQLite's (a file's lock wait, its
// fsync level, the VFS to open it with; empty: the process default).
struct ConnectionOptions {
  int busy_timeout_ms = 5000;
  // FULL: every commit is fsynced before it is acknowledged (durable across power loss); NORMAL is only
  // durable across process crashes in WAL mode.
  std::string synchronous = "FULL";
  bool read_only = false;
  std::string vfs;
};

// One prepared statement of one engine: bound by 1-based position, read by 0-based column. Owned by its connection.
class Cursor {
 public:
  virtual ~Cursor() = default;
  virtual void BindInt(int index, std::int64_t value) = 0;
  virtual void BindDouble(int index, double value) = 0;
  virtual void BindText(int index, std::string_view text) = 0;
  virtual void BindBlob(int index, std::string_view bytes) = 0;
  virtual void BindNull(int index) = 0;
  // Advances to the next row; false when done.
  virtual bool Step() = 0;
  virtual std::int64_t Int(int column) const = 0;
  virtual double Double(int column) const = 0;
  virtual std::string Text(int column) const = 0;
  virtual std::string Blob(int column) const = 0;
  virtual bool IsNull(int column) const = 0;
};

class Connection {
 public:
  virtual ~Connection() = default;
  Connection() = default;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  virtual Engine engine() const = 0;
  // Runs one or more statements without parameters or rows (schema changes, transaction control).
  virtual void Exec(std::string_view sql) = 0;
  // Rows changed by the last INSERT, UPDATE or DELETE.
  virtual std::int64_t Changes() const = 0;
  // True inside an open transaction.
  virtual bool InTransaction() const = 0;
  // Rolls back a transaction left open (a failed statement whose ROLLBACK failed as well); no-op outside one.
  virtual void EndStuckTransaction() = 0;
  // Asks the statement running on this connection (from another thread) to stop: it fails as soon as it can.
  virtual void Interrupt() = 0;
  // Transaction control for Transaction and ReadTransaction: a write transaction that takes the write lock at once,
  // and a read of the given scope (kSnapshot: its statements share one snapshot).
  virtual void BeginWrite() = 0;
  virtual void BeginRead(ReadScope scope) = 0;
  virtual void EndRead() = 0;

 private:
  friend class Statement;
  friend class ReadTransaction;
  // Statements a kOneStatement read may still prepare (-1 outside such a read); checked by Statement's constructor.
  mutable int one_statement_left_ = -1;
  // A prepared statement for `sql`, reused across calls (preparing is the largest cost of short queries); the
  // Statement hands it back with Release. A connection is used by one thread at a time.
  virtual std::unique_ptr<Cursor> Acquire(std::string_view sql) const = 0;
  virtual void Release(std::unique_ptr<Cursor> cursor) const = 0;
};

// True when `location` is a libpq connection URI (postgresql:// or postgres://); anything else is a SQLite file path.
bool IsPostgresUri(std::string_view location);

// Opens `location` with the engine it names: a libpq URI (postgresql://...) is a PostgreSQL database, anything else
// (a file path, ":memory:") a SQLite file.
std::unique_ptr<Connection> OpenConnection(const std::string& location, const ConnectionOptions& options);

class Statement {
 public:
  Statement(const Connection& connection, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Bind by 1-based position; return *this for chaining.
  Statement& Bind(int index, std::int64_t value) { return cursor_->BindInt(index, value), *this; }
  Statement& Bind(int index, double value) { return cursor_->BindDouble(index, value), *this; }
  Statement& Bind(int index, std::string_view text) { return cursor_->BindText(index, text), *this; }
  Statement& BindBlob(int index, std::string_view bytes) { return cursor_->BindBlob(index, bytes), *this; }
  Statement& BindNull(int index) { return cursor_->BindNull(index), *this; }

  // Advances to the next row; false when done.
  bool Step() { return cursor_->Step(); }
  // Runs a statement that returns no rows.
  void Run();
  // Runs an INSERT ... RETURNING id and answers the id of the row it wrote.
  std::int64_t RunReturningId();

  std::int64_t Int(int column) const { return cursor_->Int(column); }
  double Double(int column) const { return cursor_->Double(column); }
  std::string Text(int column) const { return cursor_->Text(column); }
  std::string Blob(int column) const { return cursor_->Blob(column); }
  bool IsNull(int column) const { return cursor_->IsNull(column); }

 private:
  const Connection& connection_;
  std::unique_ptr<Cursor> cursor_;
};

// A write transaction ... COMMIT; rolls back in the destructor unless Commit() ran.
class Transaction {
 public:
  explicit Transaction(Connection& connection);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void Commit();

 private:
  Connection& connection_;
  bool done_ = false;
};

// A read: with kSnapshot the statements run inside share one read snapshot (a consistent answer across several
// queries); with kOneStatement exactly one statement runs, in no transaction. Ends in the destructor; nothing to
// commit.
class ReadTransaction {
 public:
  explicit ReadTransaction(Connection& connection, ReadScope scope = ReadScope::kSnapshot);
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

}  // namespace anchordb::storage
