#include "api/audit_json.h"

#include <ctime>

#include "api/request_limits.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace params;

services::AuditQuery ParseAuditQuery(const httplib::Request& req) {
  services::AuditQuery q;
  q.since_ns = QueryTime(req, "since");
  q.until_ns = QueryTime(req, "until");
  q.actor = QueryString(req, "actor", limits::kIdLength).value_or("");
  q.action = QueryString(req, "action", limits::kIdLength).value_or("");
  q.map = QueryString(req, "map", limits::kIdLength).value_or("");
  q.after_id = QueryInteger(req, "after", 0, 0, INT64_MAX);
  q.limit = static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000));
  return q;
}

std::string IsoTimeUtc(std::int64_t time_ns) {
  std::int64_t seconds = time_ns / 1'000'000'000;
  std::int64_t fraction = time_ns % 1'000'000'000;
  if (fraction < 0) fraction += 1'000'000'000, --seconds;
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%04d-%02d-%02dT%02d:%02d:%02d.%09lldZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<long long>(fraction));
  return buf;
}

namespace {
Json StoredDocument(const std::optional<std::string>& text) {
  if (!text) return nullptr;
  Json parsed = Json::parse(*text, nullptr, false);
  return parsed.is_discarded() ? Json(*text) : parsed;
}

Json TextOrNull(const std::string& text) { return text.empty() ? Json(nullptr) : Json(text); }
}  // namespace

Json AuditEntryJson(const services::AuditEntry& e) {
  return {{"id", e.id},
          {"time_ns", e.time_ns},
          {"time", IsoTimeUtc(e.time_ns)},
          {"actor", {{"token", e.actor}, {"role", TextOrNull(e.role)}}},
          {"action", e.action},
          {"map", TextOrNull(e.map)},
          {"resource", TextOrNull(e.resource)},
          {"request_id", TextOrNull(e.request_id)},
          {"status", e.status},
          {"before", StoredDocument(e.before_json)},
          {"after", StoredDocument(e.after_json)}};
}

Json AuditPageJson(const services::AuditPage& page) {
  Json list = Json::array();
  for (const auto& e : page.entries) list.push_back(AuditEntryJson(e));
  Json out = {{"entries", list}};
  if (page.next_after) out["next_after"] = *page.next_after;
  return out;
}

}  // namespace anchordb::api
