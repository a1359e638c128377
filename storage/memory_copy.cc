#include "storage/memory_copy.h"

#include <algorithm>
#include <cstring>

#include "storage/catalog.h"
#include "storage/migrations.h"

namespace anchordb::storage {

namespace {

constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;
constexpr std::int64_t kProgressEveryRows = 5000;

void Hash(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * kFnvPrime;
}

void HashTagged(std::uint64_t& h, char tag, const void* data, std::size_t size, bool with_length) {
  Hash(h, &tag, 1);
  if (with_length) {
    const std::uint64_t n = size;
    Hash(h, &n, sizeof n);
  }
  Hash(h, data, size);
}

// Rows in key order, the same on both engines: text keys by their bytes (SQLite's BINARY; on PostgreSQL COLLATE "C",
// whatever the database's own collation).
std::string SelectAll(Engine engine, const TableInfo& t) {
  std::string sql = "SELECT ";
  for (std::size_t i = 0; i < t.columns.size(); ++i) sql += (i ? ", " : "") + QuoteIdentifier(t.columns[i].name);
  sql += " FROM " + QuoteIdentifier(t.name) + " ORDER BY ";
  const std::vector<std::string> order = t.OrderColumns();
  for (std::size_t i = 0; i < order.size(); ++i) {
    sql += (i ? ", " : "") + QuoteIdentifier(order[i]);
    const auto column = std::find_if(t.columns.begin(), t.columns.end(), [&](const ColumnInfo& c) { return c.name == order[i]; });
    if (engine == Engine::kPostgresql && column != t.columns.end() && column->kind == ValueKind::kText) sql += " COLLATE \"C\"";
  }
  return sql;
}

std::string InsertAll(const TableInfo& t) {
  std::string sql = "INSERT INTO " + QuoteIdentifier(t.name) + " (", values;
  for (std::size_t i = 0; i < t.columns.size(); ++i) {
    sql += (i ? ", " : "") + QuoteIdentifier(t.columns[i].name);
    values += i ? ", ?" : "?";
  }
  return sql + ") VALUES (" + values + ")";
}

std::int64_t CountRows(Connection& c, const TableInfo& t) {
  Statement s(c, "SELECT count(*) FROM " + QuoteIdentifier(t.name));
  s.Step();
  return s.Int(0);
}

// Adds the value of `column` of the current row to the census.
void Count(TableCensus& census, const Statement& s, int column, ValueKind kind) {
  if (s.IsNull(column)) {
    HashTagged(census.checksum, 'N', nullptr, 0, false);
    return;
  }
  switch (kind) {
    case ValueKind::kInteger: {
      const std::int64_t v = s.Int(column);
      HashTagged(census.checksum, 'I', &v, sizeof v, false);
      break;
    }
    case ValueKind::kReal: {
      const double v = s.Double(column);
      HashTagged(census.checksum, 'R', &v, sizeof v, false);
      break;
    }
    case ValueKind::kText: {
      const std::string v = s.Text(column);
      HashTagged(census.checksum, 'T', v.data(), v.size(), true);
      break;
    }
    case ValueKind::kBlob: {
      const std::string v = s.Blob(column);
      HashTagged(census.checksum, 'B', v.data(), v.size(), true);
      HashTagged(census.blob_checksum, 'B', v.data(), v.size(), true);
      census.blob_bytes += static_cast<std::int64_t>(v.size());
      break;
    }
  }
}

TableCensus CensusOf(Connection& c, const TableInfo& t) {
  TableCensus census{t.name, 0, kFnvOffset, 0, kFnvOffset};
  Statement s(c, SelectAll(c.engine(), t));
  while (s.Step()) {
    ++census.rows;
    for (std::size_t i = 0; i < t.columns.size(); ++i) Count(census, s, static_cast<int>(i), t.columns[i].kind);
  }
  return census;
}

void CopyValue(const Statement& from, Statement& to, int column, ValueKind kind) {
  if (from.IsNull(column)) {
    to.BindNull(column + 1);
    return;
  }
  switch (kind) {
    case ValueKind::kInteger: to.Bind(column + 1, from.Int(column)); break;
    case ValueKind::kReal: to.Bind(column + 1, from.Double(column)); break;
    case ValueKind::kText: to.Bind(column + 1, std::string_view(from.Text(column))); break;
    case ValueKind::kBlob: to.BindBlob(column + 1, from.Blob(column)); break;
  }
}

// The tables of both sides must be the same, column for column (both at one schema version, so they are unless a
// migration differs between the engines: then nothing is copied).
void RequireSameTables(const std::vector<TableInfo>& from, const std::vector<TableInfo>& to) {
  std::string differs;
  if (from.size() != to.size()) differs = std::to_string(from.size()) + " tables against " + std::to_string(to.size());
  for (std::size_t i = 0; differs.empty() && i < from.size(); ++i) {
    if (from[i].name != to[i].name) differs = "table " + from[i].name + " against " + to[i].name;
    else if (from[i].columns.size() != to[i].columns.size()) differs = "the columns of " + from[i].name;
    for (std::size_t k = 0; differs.empty() && k < from[i].columns.size(); ++k) {
      const ColumnInfo &a = from[i].columns[k], &b = to[i].columns[k];
      if (a.name != b.name || a.kind != b.kind) differs = "column " + from[i].name + "." + a.name + " against " + b.name;
    }
  }
  if (!differs.empty()) throw Error(ErrorCode::kInternal, "migrate: the two databases' tables differ: " + differs);
}

// PostgreSQL: each identity column's sequence continues after the largest copied id.
void MoveSequences(Connection& to, const std::vector<TableInfo>& tables) {
  if (to.engine() != Engine::kPostgresql) return;  // SQLite's AUTOINCREMENT follows inserted ids by itself
  for (const TableInfo& t : tables) {
    for (const ColumnInfo& c : t.columns) {
      if (!c.identity) continue;
      const std::string col = QuoteIdentifier(c.name), table = QuoteIdentifier(t.name);
      Statement(to, "SELECT setval(pg_get_serial_sequence(?, ?)::regclass, COALESCE((SELECT max(" + col + ") FROM " + table +
                    "), 0) + 1, false)").Bind(1, table).Bind(2, c.name).Step();
    }
  }
}

}  // namespace

std::vector<TableCensus> TakeCensus(Connection& connection) {
  std::vector<TableCensus> census;
  for (const TableInfo& t : StoredTables(connection)) census.push_back(CensusOf(connection, t));
  return census;
}

CopyReport CopyMemory(Connection& from, Connection& to, const std::function<void(const CopyProgress&)>& progress) {
  CopyReport report;
  ReadTransaction snapshot(from);
  Transaction tx(to);
  report.schema_version = UserVersion(from);
  if (UserVersion(to) != report.schema_version) {
    throw Error(ErrorCode::kConflict, "migrate: the source is at schema version " + std::to_string(report.schema_version) +
                                      " and the target at " + std::to_string(UserVersion(to)) + "; both must be the same");
  }
  const std::vector<TableInfo> tables = StoredTables(from), target_tables = StoredTables(to);
  RequireSameTables(tables, target_tables);
  for (const TableInfo& t : target_tables) {
    if (CountRows(to, t) > 0) {
      throw Error(ErrorCode::kConflict, "migrate: the target holds rows already (table " + t.name + "); copy into an empty database");
    }
  }
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableInfo& t = tables[i];
    CopyProgress p{t.name, static_cast<int>(i + 1), static_cast<int>(tables.size()), 0, CountRows(from, t)};
    Statement read(from, SelectAll(from.engine(), t));
    const std::string insert = InsertAll(t);
    while (read.Step()) {
      Statement write(to, insert);
      for (std::size_t k = 0; k < t.columns.size(); ++k) CopyValue(read, write, static_cast<int>(k), t.columns[k].kind);
      write.Run();
      if (++p.rows_done % kProgressEveryRows == 0 && progress) progress(p);
    }
    if (progress) progress(p);
    report.rows += p.rows_done;
  }
  MoveSequences(to, target_tables);
  for (const TableInfo& t : tables) report.census.push_back(CensusOf(from, t));
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const TableCensus copied = CensusOf(to, target_tables[i]);
    if (!(copied == report.census[i])) {
      throw Error(ErrorCode::kInternal, "migrate: table " + tables[i].name + " differs after the copy (" +
                                        std::to_string(report.census[i].rows) + " rows read, " +
                                        std::to_string(copied.rows) + " written, or their values); nothing was committed");
    }
    report.blob_bytes += copied.blob_bytes;
  }
  tx.Commit();
  return report;
}

}  // namespace anchordb::storage
