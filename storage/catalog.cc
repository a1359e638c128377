#include "storage/catalog.h"

#include <algorithm>
#include <map>
#include <set>

namespace anchordb::storage {

namespace {

// SQLite's type affinity of a declared column type (the rules of its documentation, section 3.1), as a value kind.
ValueKind KindOfSqliteType(std::string type) {
  std::transform(type.begin(), type.end(), type.begin(), [](unsigned char ch) { return std::toupper(ch); });
  if (type.find("INT") != std::string::npos) return ValueKind::kInteger;
  if (type.find("CHAR") != std::string::npos || type.find("CLOB") != std::string::npos ||
      type.find("TEXT") != std::string::npos) {
    return ValueKind::kText;
  }
  if (type.empty() || type.find("BLOB") != std::string::npos) return ValueKind::kBlob;
  return ValueKind::kReal;
}

ValueKind KindOfPostgresType(const std::string& type) {
  if (type == "bigint" || type == "integer" || type == "smallint" || type == "boolean") return ValueKind::kInteger;
  if (type == "double precision" || type == "real" || type == "numeric") return ValueKind::kReal;
  if (type == "bytea") return ValueKind::kBlob;
  return ValueKind::kText;
}

std::vector<TableInfo> SqliteTables(Connection& c) {
  std::vector<TableInfo> tables;
  std::set<std::string> virtual_tables;
  Statement list(c, "SELECT name, COALESCE(sql, '') FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
                    "ORDER BY name");
  std::vector<std::string> names;
  while (list.Step()) {
    const std::string name = list.Text(0);
    if (list.Text(1).rfind("CREATE VIRTUAL TABLE", 0) == 0) virtual_tables.insert(name);
    names.push_back(name);
  }
  const auto is_virtual_or_shadow = [&](const std::string& name) {
    for (const std::string& v : virtual_tables) {
      if (name == v || name == v + "_node" || name == v + "_parent" || name == v + "_rowid") return true;
    }
    return false;
  };
  for (const std::string& name : names) {
    if (IsDerivedTable(name) || is_virtual_or_shadow(name)) continue;
    TableInfo t;
    t.name = name;
    Statement columns(c, "PRAGMA table_info(" + QuoteIdentifier(name) + ")");
    while (columns.Step()) {
      t.columns.push_back({columns.Text(1), KindOfSqliteType(columns.Text(2)), static_cast<int>(columns.Int(5)), false});
    }
    Statement keys(c, "PRAGMA foreign_key_list(" + QuoteIdentifier(name) + ")");
    while (keys.Step()) {
      const std::string to = keys.Text(2);
      if (to != name && std::find(t.references.begin(), t.references.end(), to) == t.references.end()) {
        t.references.push_back(to);
      }
    }
    tables.push_back(std::move(t));
  }
  return tables;
}

std::vector<TableInfo> PostgresTables(Connection& c) {
  std::vector<TableInfo> tables;
  Statement list(c, "SELECT table_name FROM information_schema.tables WHERE table_schema = current_schema() "
                    "AND table_type = 'BASE TABLE' ORDER BY table_name COLLATE \"C\"");
  std::vector<std::string> names;
  while (list.Step()) names.push_back(list.Text(0));
  for (const std::string& name : names) {
    if (IsDerivedTable(name)) continue;
    TableInfo t;
    t.name = name;
    Statement columns(c, "SELECT column_name, data_type, is_identity FROM information_schema.columns "
                         "WHERE table_schema = current_schema() AND table_name = ? ORDER BY ordinal_position");
    columns.Bind(1, name);
    while (columns.Step()) {
      t.columns.push_back({columns.Text(0), KindOfPostgresType(columns.Text(1)), 0, columns.Text(2) == "YES"});
    }
    Statement key(c, "SELECT k.column_name, k.ordinal_position FROM information_schema.table_constraints tc "
                     "JOIN information_schema.key_column_usage k ON k.constraint_name = tc.constraint_name "
                     "AND k.table_schema = tc.table_schema AND k.table_name = tc.table_name "
                     "WHERE tc.constraint_type = 'PRIMARY KEY' AND tc.table_schema = current_schema() AND tc.table_name = ?");
    key.Bind(1, name);
    while (key.Step()) {
      for (ColumnInfo& col : t.columns) {
        if (col.name == key.Text(0)) col.primary_key_position = static_cast<int>(key.Int(1));
      }
    }
    Statement refs(c, "SELECT DISTINCT u.table_name FROM information_schema.table_constraints tc "
                      "JOIN information_schema.constraint_column_usage u ON u.constraint_name = tc.constraint_name "
                      "AND u.constraint_schema = tc.constraint_schema WHERE tc.constraint_type = 'FOREIGN KEY' "
                      "AND tc.table_schema = current_schema() AND tc.table_name = ?");
    refs.Bind(1, name);
    while (refs.Step()) {
      if (refs.Text(0) != name) t.references.push_back(refs.Text(0));
    }
    tables.push_back(std::move(t));
  }
  return tables;
}

// Every table after the tables it references (depth first in name order, so the order is the same on both engines).
std::vector<TableInfo> InDependencyOrder(std::vector<TableInfo> tables) {
  for (TableInfo& t : tables) std::sort(t.references.begin(), t.references.end());  // the catalogs list them apart
  std::map<std::string, const TableInfo*> by_name;
  for (const TableInfo& t : tables) by_name[t.name] = &t;
  std::vector<TableInfo> ordered;
  std::set<std::string> placed, visiting;
  const auto place = [&](const auto& self, const TableInfo& t) -> void {
    if (placed.count(t.name) || visiting.count(t.name)) return;  // a cycle is broken where it closes
    visiting.insert(t.name);
    for (const std::string& r : t.references) {
      auto it = by_name.find(r);
      if (it != by_name.end()) self(self, *it->second);
    }
    visiting.erase(t.name);
    placed.insert(t.name);
    ordered.push_back(t);
  };
  for (const auto& [name, t] : by_name) place(place, *t);
  return ordered;
}

}  // namespace

std::vector<std::string> TableInfo::OrderColumns() const {
  std::vector<const ColumnInfo*> key;
  for (const ColumnInfo& c : columns) {
    if (c.primary_key_position > 0) key.push_back(&c);
  }
  std::sort(key.begin(), key.end(), [](auto* a, auto* b) { return a->primary_key_position < b->primary_key_position; });
  std::vector<std::string> names;
  for (const ColumnInfo* c : key) names.push_back(c->name);
  if (names.empty()) {  // no primary key: every column, in column order
    for (const ColumnInfo& c : columns) names.push_back(c.name);
  }
  return names;
}

bool IsDerivedTable(const std::string& name) {
  return name == "schema_migrations" || name == "map_instance_versions";
}

std::vector<TableInfo> StoredTables(Connection& connection) {
  return InDependencyOrder(connection.engine() == Engine::kPostgresql ? PostgresTables(connection)
                                                                      : SqliteTables(connection));
}

std::string QuoteIdentifier(const std::string& name) {
  std::string out = "\"";
  for (char ch : name) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

}  // namespace anchordb::storage
