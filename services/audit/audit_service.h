#pragma once
// The audit trail of operator and admin actions (SPEC §8: who, what, when, before / after). The HTTP edge records
// an entry per audited request (api/audit_routes.h decides which); the CLI records token creation. Entries are
// never removed by forgetting and outlive the maps they name.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
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

  // The entry of one request, written in the change's own transaction: Begin stamps it and arms it for the calling
  // thread's next write transaction (where it is inserted with status 0: "the change committed, the answer not
  // yet known"); Finish, on the same thread after the handler, disarms it and records the outcome: an update of
  // that row, or the whole entry when no write carried it (a refused or read-only request).
  struct InFlight {
    AuditEntry entry;
    std::shared_ptr<std::int64_t> written_id = std::make_shared<std::int64_t>(0);
  };
  InFlight Begin(AuditEntry entry);
  AuditEntry Finish(InFlight& in_flight, int status, std::optional<std::string> after_json);
  // Disarms the calling thread's pending entry without recording it (Finish does it too).
  static void Disarm();
  // kInvalidArgument when limit is outside [1, 1000] or until <= since.
  AuditPage List(const AuditQuery& query);

 private:
  storage::Store& store_;
  const Clock& clock_;
};

}  // namespace anchordb::services
