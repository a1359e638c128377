#include "services/audit/audit_service.h"

#include "schema/error.h"

namespace anchordb::services {

AuditService::AuditService(storage::Store& store, const Clock& clock) : store_(store), clock_(clock) {}

AuditEntry AuditService::Record(AuditEntry entry) {
  entry.time_ns = clock_.NowNs();
  entry.id = store_.Write([&](storage::Connection& c) { return storage::InsertAuditRecord(c, entry); });
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
