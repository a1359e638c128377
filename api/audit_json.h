#pragma once
// JSON of the audit trail (GET /v1/audit): the query parameters and the page of entries.
#include "api/http_api.h"
#include "services/audit/audit_service.h"

namespace anchordb::api {

// since= / until= (ns or ISO 8601), actor=, action=, map=, after=, limit= (1..1000, default 100).
services::AuditQuery ParseAuditQuery(const httplib::Request& req);
// {"id", "time_ns", "time" (ISO 8601 UTC), "actor": {"token", "role"}, "action", "map", "resource", "request_id",
//  "status", "before", "after"}; absent values are null.
Json AuditEntryJson(const services::AuditEntry& entry);
// {"entries": [...], "next_after" when the page is full}.
Json AuditPageJson(const services::AuditPage& page);
// "2026-12-01T18:25:52.123456789Z" for nanoseconds since the Unix epoch.
std::string IsoTimeUtc(std::int64_t time_ns);

}  // namespace anchordb::api
