#pragma once
// The SQLite engine of the storage contract (storage/connection.h): thin RAII wrappers over the SQLite C API. Only
// storage/ code that needs SQLite itself (the engine, the backup API, the file's PRAGMAs, the fault VFS) includes
// this header; services and the HTTP layer see `Connection`. Error kinds as in connection.h: a constraint violation
// is kConflict (a CHECK or NOT NULL violation kInternal), SQLITE_BUSY kOverloaded, a full disk kInsufficientStorage,
// I/O errors and out of memory kUnavailable, else kInternal.
#include <sqlite3.h>

#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>

#include "storage/connection.h"

namespace anchordb::storage {

class SqliteConnection final : public Connection {
 public:
  SqliteConnection(const std::string& path, const ConnectionOptions& options);
  ~SqliteConnection() override;

  sqlite3* handle() const { return db_; }
  Engine engine() const override { return Engine::kSqlite; }
  void Exec(std::string_view sql) override;
  std::int64_t Changes() const override { return sqlite3_changes64(db_); }
  bool InTransaction() const override { return !sqlite3_get_autocommit(db_); }
  void EndStuckTransaction() override;
  void Interrupt() override { sqlite3_interrupt(db_); }
  // BEGIN IMMEDIATE: the file's write lock is taken at the start, not at the first write.
  void BeginWrite() override { Exec("BEGIN IMMEDIATE"); }
  // kOneStatement begins nothing: SQLite reads one statement outside a transaction from one snapshot.
  void BeginRead(ReadScope scope) override;
  void EndRead() override;

 private:
  std::unique_ptr<Cursor> Acquire(std::string_view sql) const override;
  void Release(std::unique_ptr<Cursor> cursor) const override;

  sqlite3* db_ = nullptr;
  // Prepared statements, one per SQL text, reused (Acquire takes one out, Release puts it back).
  mutable std::unordered_map<std::string, std::unique_ptr<Cursor>> statement_cache_;
};

// The SQLite connection behind `c`; kInternal when `c` is of another engine (for SQLite-only operations: the backup
// API, PRAGMAs of the file).
SqliteConnection& SqliteOf(Connection& c);

[[noreturn]] void ThrowSqliteError(sqlite3* db, int rc, std::string_view what);

// The error kind of a SQLite result code (see the header comment).
ErrorCode ErrorCodeOfSqlite(int rc);

}  // namespace anchordb::storage
