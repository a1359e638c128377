#pragma once
// The "forget" job kind: one forgetting run over a map (storage/forgetting.h) on a connection of the job's own, its
// outcome recorded in the same commit as the deletions, then the vacuum (stage "vacuum") when asked for.
#include <cstdint>

#include "services/jobs/job_registry.h"
#include "services/jobs/job_service.h"
#include "storage/forgetting.h"

namespace anchordb::services {

// Throws Error(kUnprocessable) for an age (seconds) negative or over 100 years (so that now - age stays
// representable in int64 nanoseconds), a relevance outside [0, 1], or a request `now_ns` after `wall_now_ns`;
// the field is named ("policy.keyframe_max_age_s", "now", ...).
void CheckForgetRequest(const storage::ForgetRequest& request, std::int64_t wall_now_ns);

// The keep rules of engine/forgetting/keep_rules.h as a forgetting run asks them (the job and `anchordb forget`).
storage::ForgetRules ForgetKeepRules();

// The kind as JobService registers it: runs on `db_path` with the settings' busy timeout and synchronous mode.
JobKind ForgetJobKind(const std::string& db_path, const JobSettings& settings);

}  // namespace anchordb::services
