#include "storage/postgres.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "schema/error.h"

namespace anchordb::storage {
namespace {

constexpr Oid kPgInt8 = 20, kPgFloat8 = 701, kPgText = 25, kPgBytea = 17;

ErrorCode ErrorCodeOfSqlState(std::string_view state) {
  if (state == "23505" || state == "23503" || state == "23P01") return ErrorCode::kConflict;
  if (state == "23514" || state == "23502") return ErrorCode::kInternal;
  if (state == "40001" || state == "40P01" || state == "57014" || state == "55P03") return ErrorCode::kOverloaded;
  if (state == "53100") return ErrorCode::kInsufficientStorage;
  if (state.substr(0, 2) == "08" || state.substr(0, 4) == "57P0" || state == "25006" || state == "53300" ||
      state == "53200") {
    return ErrorCode::kUnavailable;
  }
  return ErrorCode::kInternal;
}

int PgHexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// bytea in text form is "\x" followed by two hex digits a byte (the server's default bytea_output).
std::string DecodePgBytea(const char* text, int length) {
  if (length < 2 || text[0] != '\\' || text[1] != 'x') throw Error(ErrorCode::kInternal, "bytea not in hex form");
  std::string out(static_cast<std::size_t>(length - 2) / 2, '\0');
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int hi = PgHexDigit(text[2 + 2 * i]), lo = PgHexDigit(text[3 + 2 * i]);
    if (hi < 0 || lo < 0) throw Error(ErrorCode::kInternal, "bytea with a bad hex digit");
    out[i] = static_cast<char>(hi * 16 + lo);
  }
  return out;
}

// Whether `sql` (placeholders already as $k) names parameter k ("$1" is not named by "$12").
bool NamesParameter(const std::string& sql, int k) {
  const std::string mark = '$' + std::to_string(k);
  for (std::size_t at = sql.find(mark); at != std::string::npos; at = sql.find(mark, at + 1)) {
    const std::size_t after = at + mark.size();
    if (after == sql.size() || sql[after] < '0' || sql[after] > '9') return true;
  }
  return false;
}

// One statement of a PostgreSQL connection: parameters are collected by Bind, the statement runs at the first Step,
// and the rows of its result are walked by the following ones.
class PostgresCursor final : public Cursor {
 public:
  PostgresCursor(const PostgresConnection& connection, std::string_view sql) : connection_(connection) {
    auto [text, count] = PostgresPlaceholders(sql);
    sql_ = std::move(text);
    values_.resize(count);
    null_.assign(count, true);
    types_.assign(count, 0);
    formats_.assign(count, 0);
    // A number the text skips (?1, ?2, ?5 when optional filters are absent) is declared text: PostgreSQL refuses a
    // parameter whose type it cannot infer from any use, and SQLite ignores such gaps.
    for (int k = 1; k <= count; ++k) {
      if (!NamesParameter(sql_, k)) unused_.push_back(k - 1);
    }
    for (const int k : unused_) types_[k] = kPgText;
  }
  ~PostgresCursor() override { PQclear(result_); }

  void BindInt(int i, std::int64_t v) override { Set(i, std::to_string(v), kPgInt8, 0); }
  void BindDouble(int i, double v) override {
    char buffer[32];
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);  // shortest text that reads back exactly
    Set(i, std::string(buffer, end), kPgFloat8, 0);
  }
  void BindText(int i, std::string_view t) override { Set(i, std::string(t), kPgText, 0); }
  void BindBlob(int i, std::string_view b) override { Set(i, std::string(b), kPgBytea, 1); }
  void BindNull(int i) override {
    Check(i);
    null_[i - 1] = true;
    types_[i - 1] = std::find(unused_.begin(), unused_.end(), i - 1) != unused_.end() ? kPgText : 0;
  }

  bool Step() override {
    if (!result_) {
      std::vector<const char*> values(values_.size());
      std::vector<int> lengths(values_.size());
      for (std::size_t k = 0; k < values_.size(); ++k) {
        values[k] = null_[k] ? nullptr : values_[k].data();
        lengths[k] = static_cast<int>(values_[k].size());
      }
      result_ = connection_.Run(sql_, static_cast<int>(values_.size()), types_.data(), values.data(), lengths.data(),
                                formats_.data());
      row_ = -1;
    }
    return ++row_ < PQntuples(result_);
  }

  std::int64_t Int(int c) const override {
    const char* v = Value(c);
    if (v[0] == 't' && v[1] == '\0') return 1;  // a boolean
    if (v[0] == 'f' && v[1] == '\0') return 0;
    return std::strtoll(v, nullptr, 10);
  }
  double Double(int c) const override { return std::strtod(Value(c), nullptr); }
  std::string Text(int c) const override { return std::string(Value(c), PQgetlength(result_, row_, c)); }
  std::string Blob(int c) const override {
    if (IsNull(c)) return {};  // as SQLite: a NULL reads as no bytes
    if (PQftype(result_, c) != kPgBytea) return Text(c);
    return DecodePgBytea(Value(c), PQgetlength(result_, row_, c));
  }
  bool IsNull(int c) const override { return PQgetisnull(result_, row_, c) != 0; }

 private:
  void Check(int i) const {
    if (i < 1 || i > static_cast<int>(values_.size())) {
      throw Error(ErrorCode::kInternal, "bind: parameter " + std::to_string(i) + " of " + std::to_string(values_.size()));
    }
  }
  void Set(int i, std::string value, Oid type, int format) {
    Check(i);
    values_[i - 1] = std::move(value);
    null_[i - 1] = false;
    types_[i - 1] = type;
    formats_[i - 1] = format;
  }
  const char* Value(int c) const {
    if (!result_ || row_ < 0 || row_ >= PQntuples(result_) || c < 0 || c >= PQnfields(result_)) {
      throw Error(ErrorCode::kInternal, "column " + std::to_string(c) + " read outside a row");
    }
    return PQgetvalue(result_, row_, c);
  }

  const PostgresConnection& connection_;
  std::string sql_;
  std::vector<std::string> values_;
  std::vector<bool> null_;
  std::vector<Oid> types_;
  std::vector<int> formats_;
  std::vector<int> unused_;  // 0-based positions the text never names
  PGresult* result_ = nullptr;
  int row_ = -1;
};

}  // namespace

bool IsPostgresUri(std::string_view location) {
  return location.rfind("postgresql://", 0) == 0 || location.rfind("postgres://", 0) == 0;
}

std::pair<std::string, int> PostgresPlaceholders(std::string_view sql) {
  std::string out;
  out.reserve(sql.size() + 16);
  int next = 0, highest = 0;
  char quote = 0;
  for (std::size_t i = 0; i < sql.size(); ++i) {
    const char ch = sql[i];
    if (quote) {
      out += ch;
      if (ch == quote) quote = 0;
      continue;
    }
    if (ch == '\'' || ch == '"') {
      quote = ch;
      out += ch;
      continue;
    }
    if (ch != '?') {
      out += ch;
      continue;
    }
    int number = 0;
    std::size_t j = i + 1;
    while (j < sql.size() && sql[j] >= '0' && sql[j] <= '9') number = number * 10 + (sql[j++] - '0');
    if (j == i + 1) number = ++next;  // a plain '?' takes the next position, as SQLite numbers them
    else next = std::max(next, number);
    highest = std::max(highest, number);
    out += '$' + std::to_string(number);
    i = j - 1;
  }
  return {out, highest};
}

PostgresConnection::PostgresConnection(const std::string& uri, const ConnectionOptions& options)
    : uri_(uri), options_(options) {
  try {
    EnsureConnected();
  } catch (...) {
    if (conn_) PQfinish(conn_);  // the destructor does not run for a constructor that throws
    conn_ = nullptr;
    throw;
  }
}

PostgresConnection::~PostgresConnection() {
  if (cancel_) PQfreeCancel(cancel_);
  if (conn_) PQfinish(conn_);
}

void PostgresConnection::EnsureConnected() const {
  if (pending_results_) Drain();
  if (conn_ && PQstatus(conn_) == CONNECTION_OK) return;
  pending_begin_.clear();  // the transaction it would have begun is gone with the session
  if (conn_) {
    PQfinish(conn_);  // a fresh connection, not PQreset: no pipeline state survives
    conn_ = nullptr;
  }
  conn_ = PQconnectdb(uri_.c_str());
  prepared_.clear();  // a new server session knows none of them
  {
    std::lock_guard<std::mutex> lock(cancel_mutex_);
    if (cancel_) PQfreeCancel(cancel_);
    cancel_ = PQstatus(conn_) == CONNECTION_OK ? PQgetCancel(conn_) : nullptr;
  }
  if (!conn_ || PQstatus(conn_) != CONNECTION_OK) {
    throw Error(ErrorCode::kUnavailable, std::string("the PostgreSQL server cannot be reached for now, retry later: ") +
                                             (conn_ ? PQerrorMessage(conn_) : "out of memory"));
  }
  // The session as the SQLite engine's: waits for a lock at most busy_timeout_ms (then 55P03, kOverloaded), a
  // reader cannot write, and notices (e.g. of CREATE ... IF NOT EXISTS) stay out of the server's log.
  std::string setup = "SET client_min_messages = warning; SET lock_timeout = " +
                      std::to_string(std::max(0, options_.busy_timeout_ms)) + ";";
  if (options_.read_only) setup += " SET default_transaction_read_only = on;";
  PGresult* r = PQexec(conn_, setup.c_str());
  PQclear(r);
}

void PostgresConnection::ThrowResult(PGresult* result, std::string_view what) const {
  const char* state = result ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  std::string message = std::string(what) + ": " + (result ? PQresultErrorMessage(result) : PQerrorMessage(conn_));
  while (!message.empty() && message.back() == '\n') message.pop_back();
  ErrorCode code = state ? ErrorCodeOfSqlState(state) : ErrorCode::kUnavailable;
  if (PQstatus(conn_) != CONNECTION_OK) code = ErrorCode::kUnavailable;
  if (state) message += std::string(" (SQLSTATE ") + state + ")";
  PQclear(result);
  if (code == ErrorCode::kUnavailable) message = "storage is unavailable for now, retry later: " + message;
  if (code == ErrorCode::kInsufficientStorage) message = "the disk is full: " + message;
  throw Error(code, message);
}

void PostgresConnection::ReadThroughSync() const {
  for (int nulls = 0; nulls < 4;) {  // a NULL ends each command's results; several in a row: nothing more will come
    PGresult* r = PQgetResult(conn_);
    if (!r) {
      ++nulls;
      continue;
    }
    const ExecStatusType status = PQresultStatus(r);
    PQclear(r);
    if (status == PGRES_PIPELINE_SYNC) return;
    nulls = 0;
  }
}

void PostgresConnection::Drain() const {
  pending_results_ = false;
  if (!conn_ || PQstatus(conn_) != CONNECTION_OK) return;  // EnsureConnected reconnects
  ReadThroughSync();  // ROLLBACK's result, then the sync
  if (PQexitPipelineMode(conn_) != 1) {
    PQfinish(conn_);  // a session in an unknown state is not reused
    conn_ = nullptr;
  }
}

void PostgresConnection::BeginRead(ReadScope scope) {
  EnsureConnected();
  one_statement_read_ = scope == ReadScope::kOneStatement;
  if (!one_statement_read_) pending_begin_ = "BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY";
}

void PostgresConnection::EndRead() {
  if (one_statement_read_) {  // nothing was begun
    one_statement_read_ = false;
    return;
  }
  if (!pending_begin_.empty()) {  // no statement ran: nothing was begun
    pending_begin_.clear();
    return;
  }
  if (!conn_ || PQstatus(conn_) != CONNECTION_OK) return;
  if (PQenterPipelineMode(conn_) != 1 || PQsendQueryParams(conn_, "ROLLBACK", 0, nullptr, nullptr, nullptr, nullptr, 0) != 1 ||
      PQpipelineSync(conn_) != 1) {
    PQexitPipelineMode(conn_);
    Exec("ROLLBACK");  // the plain way
    return;
  }
  pending_results_ = true;
}

void PostgresConnection::SendPendingBegin() const {
  if (pending_begin_.empty()) return;
  const std::string begin = std::move(pending_begin_);
  pending_begin_.clear();
  PGresult* r = PQexec(conn_, begin.c_str());
  if (PQresultStatus(r) != PGRES_COMMAND_OK) ThrowResult(r, "begin");
  PQclear(r);
}

PGresult* PostgresConnection::ExecPreparedAfterBegin(const std::string& name, int parameters, const char* const* values,
                                                     const int* lengths, const int* formats) const {
  const std::string begin = std::move(pending_begin_);
  pending_begin_.clear();
  if (PQenterPipelineMode(conn_) != 1) ThrowResult(nullptr, "pipeline");
  if (PQsendQueryParams(conn_, begin.c_str(), 0, nullptr, nullptr, nullptr, nullptr, 0) != 1 ||
      PQsendQueryPrepared(conn_, name.c_str(), parameters, values, lengths, formats, 0) != 1 || PQpipelineSync(conn_) != 1) {
    pending_results_ = true;  // whatever was sent is read (and the mode left) before the next use
    ThrowResult(nullptr, "pipeline");
  }
  // BEGIN's result and its NULL, the statement's result and its NULL, then the sync.
  PGresult* begun = PQgetResult(conn_);
  PQclear(PQgetResult(conn_));
  PGresult* result = PQgetResult(conn_);
  if (result) ReadThroughSync();
  PQexitPipelineMode(conn_);
  if (PQresultStatus(begun) != PGRES_COMMAND_OK) {
    PQclear(result);
    ThrowResult(begun, "begin");
  }
  PQclear(begun);
  return result;
}

void PostgresConnection::BeginWrite() {
  // BEGIN and the write lock in one simple-query message: one round trip, not two, before a write's first statement
  // (the lock is "anchordb" read as ASCII, as one 63-bit key). A failure of either rolls back what was begun; a
  // session the server dropped while it was idle began nothing, so both are sent once more on a new session.
  static constexpr std::string_view kBeginAndLock = "BEGIN; SELECT pg_advisory_xact_lock(7020658169314698338)";
  for (int attempt = 1;; ++attempt) {
    try {
      Exec(kBeginAndLock);
      return;
    } catch (const Error& e) {
      const bool dropped_idle = e.code() == ErrorCode::kUnavailable && !(conn_ && PQstatus(conn_) == CONNECTION_OK);
      EndStuckTransaction();
      if (!dropped_idle || attempt == 2) throw;
    }
  }
}

void PostgresConnection::Exec(std::string_view sql) {
  EnsureConnected();
  SendPendingBegin();
  PGresult* r = PQexec(conn_, std::string(sql).c_str());
  const ExecStatusType status = PQresultStatus(r);
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) ThrowResult(r, "exec");
  PQclear(r);
}

bool PostgresConnection::InTransaction() const {
  if (pending_results_) Drain();
  if (!conn_) return false;
  const PGTransactionStatusType s = PQtransactionStatus(conn_);
  return s == PQTRANS_INTRANS || s == PQTRANS_INERROR || s == PQTRANS_ACTIVE;
}

void PostgresConnection::EndStuckTransaction() {
  if (!conn_ || PQstatus(conn_) != CONNECTION_OK || !InTransaction()) return;
  PQclear(PQexec(conn_, "ROLLBACK"));
}

void PostgresConnection::Interrupt() {
  std::lock_guard<std::mutex> lock(cancel_mutex_);
  if (!cancel_) return;
  char error[256];
  PQcancel(cancel_, error, sizeof error);  // best effort: a statement that already ended is not affected
}

PGresult* PostgresConnection::Run(const std::string& sql, int parameters, const Oid* types, const char* const* values,
                                  const int* lengths, const int* formats) const {
  EnsureConnected();
  // The first statement of a read transaction (or the only one of a one-statement read) on a session the server
  // dropped meanwhile (a restart or failover while the connection was idle: libpq learns it only now) runs again on a
  // new session: nothing was read or written yet. Any other statement's failure is the caller's (a write may have
  // been applied before the loss).
  const std::string begin = pending_begin_;
  try {
    return RunOnce(sql, parameters, types, values, lengths, formats);
  } catch (const Error& e) {
    const bool first_of_read = !begin.empty() || one_statement_read_;
    if (!first_of_read || e.code() != ErrorCode::kUnavailable || (conn_ && PQstatus(conn_) == CONNECTION_OK)) throw;
    EnsureConnected();
    pending_begin_ = begin;
    return RunOnce(sql, parameters, types, values, lengths, formats);
  }
}

PGresult* PostgresConnection::RunOnce(const std::string& sql, int parameters, const Oid* types, const char* const* values,
                                      const int* lengths, const int* formats) const {
  std::string key = sql;
  key += '\0';
  for (int k = 0; k < parameters; ++k) key += std::to_string(types[k]) + ",";
  auto it = prepared_.find(key);
  if (it == prepared_.end()) {
    const std::string name = "s" + std::to_string(prepared_.size() + 1);
    PGresult* p = PQprepare(conn_, name.c_str(), sql.c_str(), parameters, types);
    if (PQresultStatus(p) != PGRES_COMMAND_OK) ThrowResult(p, "prepare");
    PQclear(p);
    it = prepared_.emplace(std::move(key), name).first;
  }
  PGresult* r = pending_begin_.empty() ? PQexecPrepared(conn_, it->second.c_str(), parameters, values, lengths, formats, 0)
                                        : ExecPreparedAfterBegin(it->second, parameters, values, lengths, formats);
  const ExecStatusType status = PQresultStatus(r);
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) ThrowResult(r, "step");
  const char* tuples = PQcmdTuples(r);
  changes_ = tuples && *tuples ? std::strtoll(tuples, nullptr, 10) : 0;
  return r;
}

std::unique_ptr<Cursor> PostgresConnection::Acquire(std::string_view sql) const {
  return std::make_unique<PostgresCursor>(*this, sql);
}

void PostgresConnection::Release(std::unique_ptr<Cursor> cursor) const { cursor.reset(); }

}  // namespace anchordb::storage
