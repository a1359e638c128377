#include "services/audit/audit_service.h"

#include "schema/error.h"

namespace anchordb::services {

AuditService::AuditService(storage::Store& store, const Clock& clock) : store_(store), clock_(clock) {}

AuditEntry AuditService::Record(AuditEntry entry) {
  entry.time_ns = clock_.NowNs();
  entry.id = store_.Write([&](storage::Connection& c) { return storage::InsertAuditRecord(c, entry); });
  return entry;
}

AuditService::InFlight AuditService::Begin(AuditEntry entry) {
  InFlight in_flight;
  entry.time_ns = clock_.NowNs();
  entry.status = 0;
  entry.after_json.reset();
  in_flight.entry = entry;
  storage::SetBeforeCommitHook([entry, id = in_flight.written_id](storage::Connection& c) {
    *id = storage::InsertAuditRecord(c, entry);
  });
  return in_flight;
}

void AuditService::Disarm() { storage::SetBeforeCommitHook(nullptr); }

AuditEntry AuditService::Finish(InFlight& in_flight, int status, std::optional<std::string> after_json) {
  Disarm();
  AuditEntry& entry = in_flight.entry;
  entry.status = status;
  entry.after_json = std::move(after_json);
  const std::int64_t id = *in_flight.written_id;
  const bool updated = id > 0 && store_.Write([&](storage::Connection& c) {
    return storage::UpdateAuditOutcome(c, id, entry.status, entry.after_json);
  });
  if (updated) {
    entry.id = id;
  } else {  // no write carried it (or the one that did rolled back)
    entry.id = store_.Write([&](storage::Connection& c) { return storage::InsertAuditRecord(c, entry); });
  }
  return entry;
}

AuditPage AuditService::List(const AuditQuery& query) {
  if (query.limit < 1 || query.limit > 1000) throw Error(ErrorCode::kInvalidArgument, "limit must be in [1, 1000]", "limit");
  if (query.since_ns && query.until_ns && *query.until_ns <= *query.since_ns) {
    throw Error(ErrorCode::kUnprocessable, "until must be later than since", "until");
  }
  AuditPage page;
  page.entries = store_.Read([&](storage::Connection& c) { return storage::ListAuditRecords(c, query); });
  if (static_cast<int>(page.entries.size()) == query.limit) page.next_after = page.entries.back().id;
  return page;
}

}  // namespace anchordb::services
