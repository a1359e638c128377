#pragma once
// The audit trail of operator and admin actions (SPEC §8: who, what, when, before / after). The HTTP edge records
// an entry per audited request (api/audit_routes.h decides which); the CLI records token creation. Entries are
// never removed by forgetting and outlive the maps they name.
#include <cstdint>
#include <optional>
#include <vector>

#include "schema/clock.h"
#include "storage/audit_repository.h"
#include "storage/store.h"

namespace anchordb::services {

// One entry (fields documented in storage/audit_repository.h); `id` and `time_ns` are set by Record.
using AuditEntry = storage::AuditRecord;
// Filters and page position of a listing (limit in [1, 1000]).
using AuditQuery = storage::AuditFilter;

struct AuditPage {
  std::vector<AuditEntry> entries;       // in id (= time) order
  std::optional<std::int64_t> next_after;  // pass as after= for the next page; set when the page is full
};

class AuditService {
 public:
  // `clock` stamps entries; both must outlive the service.
  AuditService(storage::Store& store, const Clock& clock = SystemClock::Instance());

  // Stamps `entry` with the clock and commits it; returns the stored entry (with its id).
  AuditEntry Record(AuditEntry entry);
  // kInvalidArgument when limit is outside [1, 1000] or until <= since.
  AuditPage List(const AuditQuery& query);

 private:
  storage::Store& store_;
  const Clock& clock_;
};

}  // namespace anchordb::services
