#include "api/job_json.h"

#include <map>
#include <mutex>

#include "api/request_limits.h"
#include "api/stored_document_json.h"
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

std::mutex writers_mutex;
std::map<std::string, JobDocumentWriters>& Writers() {
  static std::map<std::string, JobDocumentWriters> writers;
  return writers;
}

Json Document(const std::string& kind, std::int64_t job, const services::JobDocument& d, bool result) {
  DocumentJsonWriter writer = [&kind](const std::string&, const std::string&) -> Json {
    throw Error(ErrorCode::kInternal, "this server has no writer for the documents of job kind '" + kind + "'");
  };
  {
    std::lock_guard<std::mutex> lock(writers_mutex);
    const auto it = Writers().find(kind);
    if (it != Writers().end() && (result ? it->second.result : it->second.request)) {
      writer = result ? it->second.result : it->second.request;
    }
  }
  return StoredDocumentJson(d, "job " + std::to_string(job) + (result ? "'s result" : "'s request"), writer);
}

Json PolicyJson(const services::ForgetPolicy& p) {
  return {{"superseded_models", p.drop_superseded},
          {"keyframe_max_age_s", p.keyframe_max_age_s ? Json(*p.keyframe_max_age_s) : Json(nullptr)},
          {"keep_relevance_at_least", p.keep_relevance_at_least},
          {"event_max_age_s", p.event_max_age_s ? Json(*p.event_max_age_s) : Json(nullptr)},
          {"vacuum", p.vacuum}};
}

Json Counts(const storage::ForgetReport& r) {
  return {{"models_state_dropped", r.models_state_dropped.size()},
          {"models_deleted", r.models_deleted.size()},
          {"events_deleted", r.events_deleted.size()},
          {"keyframes_deleted", r.keyframes_deleted.size()},
          {"segments_deleted", r.segments_deleted.size()},
          {"keyframes_of_abandoned_open_scenes_deleted", r.keyframes_of_abandoned_scenes},
          {"features_deleted", r.features_deleted},
          {"features_deduplicated", r.features_deduplicated}};
}

Json Kept(const storage::ForgetReport& r) {
  return {{"keyframes_pinned", r.keyframes_kept_pinned},
          {"keyframes_relevant", r.keyframes_kept_relevant},
          {"keyframes_referenced", r.keyframes_kept_referenced},
          {"keyframes_of_open_scenes", r.keyframes_kept_open_scene},
          {"events_pinned", r.events_kept_pinned},
          {"events_labelled", r.events_kept_labelled},
          {"events_latest_of_instance", r.events_kept_latest},
          {"events_of_pinned_instances", r.events_kept_pinned_instance}};
}

}  // namespace

void RegisterJobDocumentWriters(const std::string& kind, JobDocumentWriters writers) {
  std::lock_guard<std::mutex> lock(writers_mutex);
  Writers()[kind] = std::move(writers);
}

void RegisterBuiltInJobDocumentWriters() {
  RegisterJobDocumentWriters("forget", {[](const std::string& d, const std::string& what) { return ToJson(storage::DecodeForgetRequest(d, what)); },
                                        [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeForgetReport(d, what)); }});
  RegisterJobDocumentWriters("backup", {[](const std::string& d, const std::string& what) {
                                          return Json{{"file", storage::DecodeBackupRequest(d, what).file}};
                                        },
                                        [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeBackupReport(d, what)); }});
}

Json ToJson(const services::ForgetRequest& r) {
  Json j = {{"policy", PolicyJson(r.policy)}, {"dry_run", r.dry_run}};
  if (r.now_ns) j["now"] = *r.now_ns;
  return j;
}

Json ToJson(const storage::ForgetReport& r) {
  Json j = {
      {"map", r.map_id},
      {"dry_run", r.dry_run},
      {"committed", r.committed},
      {"now_ns", r.now_ns},
      {"policy", PolicyJson(r.policy)},
      {"models_state_dropped", r.models_state_dropped},
      {"models_deleted", r.models_deleted},
      {"events_deleted", r.events_deleted},
      {"keyframes_deleted", r.keyframes_deleted},
      {"segments_deleted", r.segments_deleted},
      {"features_deduplicated", r.features_deduplicated},
      {"counts", Counts(r)},
      {"kept", Kept(r)},
      {"notes", {"features are de-duplicated on insert (settings features_dedup_*); features_deleted went with the "
                 "deleted keyframes, features_deduplicated were exact repeats"}},
      {"bytes_freed_estimate", r.bytes_freed_estimate},
      {"pages",
       {{"page_size", r.page_size},
        {"before", {{"page_count", r.page_count_before}, {"freelist_count", r.freelist_before}}},
        {"after", {{"page_count", r.page_count_after}, {"freelist_count", r.freelist_after}}}}},
      {"seconds", r.seconds},
  };
  if (!r.vacuum_mode.empty()) {
    j["vacuum"] = {{"mode", r.vacuum_mode}};
    if (r.vacuum_mode != "skipped (dry run)") {
      j["vacuum"]["file_bytes_before"] = r.file_bytes_before;
      j["vacuum"]["file_bytes_after"] = r.file_bytes_after;
      j["vacuum"]["page_count_after"] = r.page_count_after_vacuum;
      j["vacuum"]["freelist_count_after"] = r.freelist_after_vacuum;
    }
  }
  return j;
}

Json ToJson(const storage::BackupReport& r) {
  return {{"file", r.file},         {"bytes", r.bytes},         {"pages", r.pages},
          {"restarts", r.restarts}, {"integrity", r.integrity}, {"duration_s", r.duration_s}};
}

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
          {"request", Document(t.kind, t.job, t.request, false)}};
}

Json ToJson(const services::JobView& j) {
  return {{"id", j.id},
          {"kind", j.kind},
          {"map", j.map ? Json(*j.map) : Json(nullptr)},
          {"status", services::JobStatusId(j.status)},
          {"stage", j.stage},
          {"progress", j.progress},
          {"request", Document(j.kind, j.id, j.request, false)},
          {"result", j.result ? Document(j.kind, j.id, *j.result, true) : Json(nullptr)},
          {"error", j.error ? Json(*j.error) : Json(nullptr)},
          {"created_ns", j.created_ns},
          {"updated_ns", j.updated_ns}};
}

}  // namespace anchordb::api
