#pragma once
// Rows of the audit trail (migrations/0008_audit.sql): one per audited operator or admin action. The table has no
// foreign key: entries outlive the maps they name, and forgetting never touches them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct AuditRecord {
  std::int64_t id = 0;       // assigned on insert, increasing
  std::int64_t time_ns = 0;  // since the Unix epoch
  std::string actor;         // token id, "loopback" (auth off) or "cli"
  std::string role;          // reader | writer | admin, or "" when no token was presented
  std::string action;        // "instance.label", "map.delete", ...
  std::string map;           // "" when the action names no map
  std::string resource;      // the resource id within the map ("instance 7"), or ""
  std::string request_id;    // X-Request-Id, or "" outside HTTP
  int status = 0;            // HTTP status of the answer (0 outside HTTP)
  std::optional<std::string> before_json;  // the changed record before / after (JSON text), when there is one
  std::optional<std::string> after_json;
};

// Filters of a listing; empty strings match everything. Entries come in id order, after `after_id`.
struct AuditFilter {
  std::optional<std::int64_t> since_ns;  // time_ns >= since_ns
  std::optional<std::int64_t> until_ns;  // time_ns < until_ns
  std::string actor;
  std::string action;
  std::string map;
  std::int64_t after_id = 0;
  int limit = 100;  // at most this many rows
};

// Inserts `record` (its id is ignored) and returns the new id.
std::int64_t InsertAuditRecord(Connection& c, const AuditRecord& record);
std::vector<AuditRecord> ListAuditRecords(Connection& c, const AuditFilter& filter);
// Sets the outcome of entry `id`; false when there is no such entry.
bool UpdateAuditOutcome(Connection& c, std::int64_t id, int status, const std::optional<std::string>& after_json);

}  // namespace anchordb::storage
