#pragma once
// What a database holds, read from its engine's catalog (SQLite's sqlite_master and PRAGMAs, PostgreSQL's
// information_schema and pg_catalog): the tables the migrations made, their columns with one of four value kinds,
// primary keys, identity columns and the tables each references. Used to copy a whole memory between engines
// (storage/memory_copy.h) without a list of tables that would drift from the migrations.
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

// The four kinds a stored value has on both engines (INTEGER/BIGINT, REAL/DOUBLE PRECISION, TEXT, BLOB/BYTEA).
enum class ValueKind { kInteger, kReal, kText, kBlob };

struct ColumnInfo {
  std::string name;
  ValueKind kind = ValueKind::kText;
  int primary_key_position = 0;  // 1-based position in the primary key; 0: not part of it
  bool identity = false;         // PostgreSQL: GENERATED ... AS IDENTITY (its sequence follows a copy)
};

struct TableInfo {
  std::string name;
  std::vector<ColumnInfo> columns;       // in the table's column order
  std::vector<std::string> references;   // tables its foreign keys name (itself excluded)
  // The columns to order rows by, so that both engines list them alike: the primary key's, in key order.
  std::vector<std::string> OrderColumns() const;
};

// Tables kept from others, never copied: SQLite's R*-trees and their shadow tables (the index keeps them), the
// per-map change counts of map_instance_versions (triggers count the copied rows afresh) and schema_migrations (each
// database's own migrations write it).
bool IsDerivedTable(const std::string& name);

// The stored (not derived) tables of the database, every table after the tables it references.
std::vector<TableInfo> StoredTables(Connection& connection);

// `name` quoted as an SQL identifier (the same on both engines).
std::string QuoteIdentifier(const std::string& name);

}  // namespace anchordb::storage
