#pragma once
// JSON <-> the typed requests and results of JobService (the :forget, /backups and /jobs routes).
#include "schema/json_io.h"
#include "services/jobs/job_types.h"
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

// {"job", "status": "queued", "kind", "map", "request"}
Json ToJson(const services::JobTicket& ticket);
// {id, kind, map, status, stage, progress, request, result, error, created_ns, updated_ns}
Json ToJson(const services::JobView& job);

}  // namespace anchordb::api
