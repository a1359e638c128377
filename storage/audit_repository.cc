#include "storage/audit_repository.h"

namespace anchordb::storage {
namespace {
void BindOptionalText(Statement& s, int index, const std::optional<std::string>& text) {
  if (text) s.Bind(index, std::string_view(*text));
  else s.BindNull(index);
}
}  // namespace

std::int64_t InsertAuditRecord(Connection& c, const AuditRecord& r) {
  Statement s(c,
              "INSERT INTO audit_log (time_ns, actor, role, action, map_id, resource, request_id, status, before_json, "
              "after_json) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id");
  s.Bind(1, r.time_ns).Bind(2, r.actor).Bind(3, r.role).Bind(4, r.action).Bind(5, r.map).Bind(6, r.resource);
  s.Bind(7, r.request_id).Bind(8, static_cast<std::int64_t>(r.status));
  BindOptionalText(s, 9, r.before_json);
  BindOptionalText(s, 10, r.after_json);
  return s.RunReturningId();
}

bool UpdateAuditOutcome(Connection& c, std::int64_t id, int status, const std::optional<std::string>& after_json) {
  Statement s(c, "UPDATE audit_log SET status = ?, after_json = ? WHERE id = ?");
  s.Bind(1, static_cast<std::int64_t>(status));
  BindOptionalText(s, 2, after_json);
  s.Bind(3, id).Run();
  return c.Changes() > 0;
}

std::vector<AuditRecord> ListAuditRecords(Connection& c, const AuditFilter& f) {
  Statement s(c,
              "SELECT id, time_ns, actor, role, action, map_id, resource, request_id, status, before_json, after_json "
              "FROM audit_log WHERE id > ?1 AND (CAST(?2 AS BIGINT) IS NULL OR time_ns >= ?2) "
              "AND (CAST(?3 AS BIGINT) IS NULL OR time_ns < ?3) "
              "AND (?4 = '' OR actor = ?4) AND (?5 = '' OR action = ?5) AND (?6 = '' OR map_id = ?6) "
              "ORDER BY id LIMIT ?7");
  s.Bind(1, f.after_id);
  if (f.since_ns) s.Bind(2, *f.since_ns); else s.BindNull(2);
  if (f.until_ns) s.Bind(3, *f.until_ns); else s.BindNull(3);
  s.Bind(4, f.actor).Bind(5, f.action).Bind(6, f.map).Bind(7, static_cast<std::int64_t>(f.limit));
  std::vector<AuditRecord> out;
  while (s.Step()) {
    AuditRecord r;
    r.id = s.Int(0), r.time_ns = s.Int(1), r.actor = s.Text(2), r.role = s.Text(3), r.action = s.Text(4);
    r.map = s.Text(5), r.resource = s.Text(6), r.request_id = s.Text(7), r.status = static_cast<int>(s.Int(8));
    if (!s.IsNull(9)) r.before_json = s.Text(9);
    if (!s.IsNull(10)) r.after_json = s.Text(10);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace anchordb::storage
