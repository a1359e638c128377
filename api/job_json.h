#pragma once
// JSON <-> the typed requests and results of JobService (the :forget, /backups and /jobs routes).
#include <functional>
#include <string>

#include "schema/json_io.h"
#include "services/jobs/job_types.h"

namespace anchordb::api {

using json::Json;

// {"policy": {"superseded_models", "keyframe_max_age_s", "keep_relevance_at_least", "event_max_age_s", "vacuum"},
// "dry_run", "now"}; every key optional, an age null = never expires. Not an object: kInvalidJson; unknown keys and
// wrong types: Error kInvalidArgument naming the field. The ranges are checked by JobService::SubmitForget
// (services/jobs/forget_job.h: CheckForgetRequest).
services::ForgetRequest ParseForgetRequest(const Json& body);
// {"label"?: id}
services::BackupRequest ParseBackupRequest(const Json& body);

// The JSON of a job kind's request and result, each from its encoded document (a services/ decoder). Each capability's
// routes file registers its kind's writers when it registers its routes (the built-in forget and backup: job_routes);
// registering a kind again replaces its writers.
struct JobDocumentWriters {
  std::function<Json(const std::string& encoded, const std::string& what)> request;
  std::function<Json(const std::string& encoded, const std::string& what)> result;
};
void RegisterJobDocumentWriters(const std::string& kind, JobDocumentWriters writers);
// The writers of "forget" and "backup".
void RegisterBuiltInJobDocumentWriters();

// The stored forms of the built-in jobs as served (also printed by the CLI's forget and backup).
Json ToJson(const services::ForgetRequest& request);
Json ToJson(const storage::ForgetReport& report);
Json ToJson(const storage::BackupReport& report);

// {"job", "status": "queued", "kind", "map", "request"}. A document written before migration 0024 shows its stored
// JSON text as it was; one that cannot be read (a corrupt row, a kind this server does not know) shows as
// {"unreadable": why}, so that one bad row does not hide the others.
Json ToJson(const services::JobTicket& ticket);
// {id, kind, map, status, stage, progress, request, result, error, created_ns, updated_ns}
Json ToJson(const services::JobView& job);

}  // namespace anchordb::api
