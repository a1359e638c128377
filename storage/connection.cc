#include "storage/connection.h"

#include "storage/postgres.h"
#include "storage/sqlite.h"

namespace anchordb::storage {

namespace {
const Connection& CountedAgainstOneStatementRead(const Connection& connection, int& left) {
  if (left == 0) throw Error(ErrorCode::kInternal, "a one-statement read ran a second statement (read with a snapshot)");
  if (left > 0) --left;
  return connection;
}
}  // namespace

Statement::Statement(const Connection& connection, std::string_view sql)
    : connection_(CountedAgainstOneStatementRead(connection, connection.one_statement_left_)),
      cursor_(connection.Acquire(sql)) {}

Statement::~Statement() { connection_.Release(std::move(cursor_)); }

void Statement::Run() {
  while (Step()) {
  }
}

std::int64_t Statement::RunReturningId() {
  if (!Step()) throw Error(ErrorCode::kInternal, "an INSERT ... RETURNING id answered no row");
  const std::int64_t id = Int(0);
  Run();  // to the end: the statement is complete before it goes back to the cache
  return id;
}

ReadTransaction::ReadTransaction(Connection& connection, ReadScope scope) : connection_(connection) {
  connection_.EndStuckTransaction();  // an earlier snapshot whose end failed (out of memory) must not stay open
  connection_.BeginRead(scope);
  connection_.one_statement_left_ = scope == ReadScope::kOneStatement ? 1 : -1;
}

ReadTransaction::~ReadTransaction() {
  connection_.one_statement_left_ = -1;
  try {
    connection_.EndRead();
  } catch (...) {
    // Ending a read transaction cannot lose anything; a failure leaves the engine to end it at the next begin or close.
  }
}

Transaction::Transaction(Connection& connection) : connection_(connection) {
  connection_.EndStuckTransaction();  // a failed write whose rollback failed too must not stay open
  connection_.BeginWrite();
}

Transaction::~Transaction() {
  if (!done_) {
    try {
      connection_.Exec("ROLLBACK");
    } catch (...) {
      // A failed rollback leaves the engine to roll back on close; nothing more can be done in a destructor.
    }
  }
}

void Transaction::Commit() {
  connection_.Exec("COMMIT");
  done_ = true;
}

std::unique_ptr<Connection> OpenConnection(const std::string& location, const ConnectionOptions& options) {
  if (IsPostgresUri(location)) return std::make_unique<PostgresConnection>(location, options);
  return std::make_unique<SqliteConnection>(location, options);
}

}  // namespace anchordb::storage
