// A forget job's request, and the forgetting and backup reports, as the JSON documents stored with their jobs.
#include "services/jobs/job_documents.h"

#include <nlohmann/json.hpp>

#include "schema/error.h"

namespace anchordb::services {
namespace {

using Json = nlohmann::json;

Json PolicyJson(const storage::ForgetPolicy& p) {
  return {{"superseded_models", p.drop_superseded},
          {"keyframe_max_age_s", p.keyframe_max_age_s ? Json(*p.keyframe_max_age_s) : Json(nullptr)},
          {"keep_relevance_at_least", p.keep_relevance_at_least},
          {"event_max_age_s", p.event_max_age_s ? Json(*p.event_max_age_s) : Json(nullptr)},
          {"vacuum", p.vacuum}};
}

Json ReportJson(const storage::ForgetReport& r) {
  Json j = {
      {"map", r.map_id},
      {"dry_run", r.dry_run},
      {"committed", r.committed},
      {"now_ns", r.now_ns},
      {"policy", PolicyJson(r.policy)},
      {"models_state_dropped", Json(r.models_state_dropped)},
      {"models_deleted", Json(r.models_deleted)},
      {"events_deleted", Json(r.events_deleted)},
      {"keyframes_deleted", Json(r.keyframes_deleted)},
      {"segments_deleted", Json(r.segments_deleted)},
      {"features_deduplicated", r.features_deduplicated},
      {"counts",
       {{"models_state_dropped", r.models_state_dropped.size()},
        {"models_deleted", r.models_deleted.size()},
        {"events_deleted", r.events_deleted.size()},
        {"keyframes_deleted", r.keyframes_deleted.size()},
        {"segments_deleted", r.segments_deleted.size()},
        {"keyframes_of_abandoned_open_scenes_deleted", r.keyframes_of_abandoned_scenes},
        {"features_deleted", r.features_deleted},
        {"features_deduplicated", r.features_deduplicated}}},
      {"kept",
       {{"keyframes_pinned", r.keyframes_kept_pinned},
        {"keyframes_relevant", r.keyframes_kept_relevant},
        {"keyframes_referenced", r.keyframes_kept_referenced},
        {"keyframes_of_open_scenes", r.keyframes_kept_open_scene},
        {"events_pinned", r.events_kept_pinned},
        {"events_labelled", r.events_kept_labelled},
        {"events_latest_of_instance", r.events_kept_latest},
        {"events_of_pinned_instances", r.events_kept_pinned_instance}}},
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

std::optional<double> AgeOf(const Json& policy, const char* key) {
  const Json& v = policy.at(key);
  return v.is_null() ? std::nullopt : std::optional<double>(v.get<double>());
}

}  // namespace

std::string ForgetRequestDocument(const storage::ForgetRequest& r) {
  Json stored = {{"policy", PolicyJson(r.policy)}, {"dry_run", r.dry_run}};
  if (r.now_ns) stored["now"] = *r.now_ns;
  return stored.dump();
}

storage::ForgetRequest ForgetRequestFromDocument(const std::string& text) {
  try {
    const Json j = Json::parse(text);
    storage::ForgetRequest r;
    const Json& p = j.at("policy");
    r.policy.drop_superseded = p.at("superseded_models").get<bool>();
    r.policy.keyframe_max_age_s = AgeOf(p, "keyframe_max_age_s");
    r.policy.keep_relevance_at_least = p.at("keep_relevance_at_least").get<double>();
    r.policy.event_max_age_s = AgeOf(p, "event_max_age_s");
    r.policy.vacuum = p.at("vacuum").get<bool>();
    r.dry_run = j.at("dry_run").get<bool>();
    if (j.contains("now")) r.now_ns = j.at("now").get<std::int64_t>();
    return r;
  } catch (const Json::exception& e) {
    throw Error(ErrorCode::kInvalidArgument, std::string("not a forgetting request: ") + e.what(), "request");
  }
}

std::string ForgetReportDocument(const storage::ForgetReport& report) { return ReportJson(report).dump(); }

std::string BackupReportDocument(const storage::BackupReport& r) {
  return Json{{"file", r.file},         {"bytes", r.bytes},         {"pages", r.pages},
              {"restarts", r.restarts}, {"integrity", r.integrity}, {"duration_s", r.duration_s}}
      .dump();
}

std::string BackupRequestDocument(const std::string& file) { return Json{{"file", file}}.dump(); }

std::string BackupFileFromDocument(const std::string& text) {
  const Json j = Json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("file") || !j["file"].is_string()) {
    throw Error(ErrorCode::kInvalidArgument, "a backup request names its file", "file");
  }
  return j["file"].get<std::string>();
}

}  // namespace anchordb::services
