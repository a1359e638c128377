#pragma once
// A whole memory copied from one database into another, of either engine (`anchordb migrate-to`): a robot's SQLite
// file becomes a map of a site's PostgreSQL database, and back. Rows keep their ids; the copy is verified by a
// census of both sides (row counts and checksums of every value and of the blobs) before it is committed.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct TableCensus {
  std::string table;
  std::int64_t rows = 0;
  std::uint64_t checksum = 0;       // FNV-1a (64 bit) over every value of every row, rows in primary-key order
  std::int64_t blob_bytes = 0;
  std::uint64_t blob_checksum = 0;  // FNV-1a over the blob values alone, in the same order
  bool operator==(const TableCensus&) const = default;
};

// The stored tables (storage/catalog.h) in dependency order. A value is hashed with its kind and its bytes: integers
// and doubles as their 8 bytes, text and blobs with their length, NULL as its own tag; so equal censuses mean equal
// rows (up to a 64-bit collision), whichever engine holds them.
std::vector<TableCensus> TakeCensus(Connection& connection);

struct CopyProgress {
  std::string table;
  int table_index = 0;  // 1-based
  int tables = 0;
  std::int64_t rows_done = 0;
  std::int64_t rows_total = 0;
};

struct CopyReport {
  int schema_version = 0;
  std::vector<TableCensus> census;  // the source's, equal to the target's after the copy
  std::int64_t rows = 0;
  std::int64_t blob_bytes = 0;
};

// Copies every stored table of `from` into `to`: one read snapshot of `from`, one write transaction of `to`, rows
// in dependency and key order with their ids; PostgreSQL identity sequences are moved past the copied ids. Both must
// be at the same schema version and `to` must hold no rows (else Error kConflict, nothing written). The census of
// `to` is taken inside the transaction: when it differs from `from`'s the copy is rolled back (Error kInternal
// naming the first table that differs). `progress` is called every few thousand rows and at each table's end.
CopyReport CopyMemory(Connection& from, Connection& to, const std::function<void(const CopyProgress&)>& progress);

}  // namespace anchordb::storage
