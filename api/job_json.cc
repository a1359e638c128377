#include "api/job_json.h"
#include "api/request_limits.h"

#include "schema/error.h"

namespace anchordb::api {
namespace {

// An age in seconds: absent = `fallback`, null = never expires.
std::optional<double> ParseAge(const Json& policy, const std::string& key, std::optional<double> fallback) {
  auto it = policy.find(key);
  if (it == policy.end()) return fallback;
  if (it->is_null()) return std::nullopt;
  return json::AsFiniteNumber(*it, "policy." + key);
}

// A stored document as served (text that is not JSON shows as a discarded value, as before).
Json Document(const std::string& text) { return Json::parse(text, nullptr, false); }

}  // namespace

services::ForgetRequest ParseForgetRequest(const Json& body) {
  if (!body.is_object()) throw Error(ErrorCode::kInvalidJson, "request body must be a JSON object");
  json::RejectUnknownKeys(body, {"policy", "dry_run", "now"});
  services::ForgetRequest out;
  out.dry_run = json::BoolOr(body, "dry_run", false);
  if (body.contains("now") && !body["now"].is_null()) out.now_ns = json::AsStampNs(body["now"], "now");
  auto it = body.find("policy");
  if (it == body.end() || it->is_null()) return out;
  const Json& p = *it;
  if (!p.is_object()) throw Error(ErrorCode::kInvalidArgument, "policy must be an object", "policy");
  json::RejectUnknownKeys(p, {"superseded_models", "keyframe_max_age_s", "keep_relevance_at_least", "event_max_age_s",
                              "vacuum"},
                          "policy");
  services::ForgetPolicy& policy = out.policy;
  policy.drop_superseded = json::BoolOr(p, "superseded_models", policy.drop_superseded, "policy");
  policy.keyframe_max_age_s = ParseAge(p, "keyframe_max_age_s", policy.keyframe_max_age_s);
  policy.event_max_age_s = ParseAge(p, "event_max_age_s", policy.event_max_age_s);
  policy.keep_relevance_at_least = json::FiniteNumberOr(p, "keep_relevance_at_least", policy.keep_relevance_at_least, "policy");
  policy.vacuum = json::BoolOr(p, "vacuum", policy.vacuum, "policy");
  return out;
}

services::BackupRequest ParseBackupRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"label"});
  return {json::OptionalString(body, "label", limits::kBackupLabelLength).value_or("")};
}

Json ToJson(const services::JobTicket& t) {
  return {{"job", t.job}, {"status", "queued"}, {"kind", t.kind}, {"map", t.map ? Json(*t.map) : Json(nullptr)},
          {"request", Document(t.request_json)}};
}

Json ToJson(const services::JobView& j) {
  return {{"id", j.id},
          {"kind", j.kind},
          {"map", j.map ? Json(*j.map) : Json(nullptr)},
          {"status", services::JobStatusId(j.status)},
          {"stage", j.stage},
          {"progress", j.progress},
          {"request", Document(j.request_json)},
          {"result", j.result_json ? Document(*j.result_json) : Json(nullptr)},
          {"error", j.error ? Json(*j.error) : Json(nullptr)},
          {"created_ns", j.created_ns},
          {"updated_ns", j.updated_ns}};
}

}  // namespace anchordb::api
