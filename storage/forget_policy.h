#pragma once
// What a forgetting run keeps and removes (storage/forgetting.h), as plain types: the policy and the request of a
// forgetting job. The JSON forms are the HTTP edge's (api/job_json.h) and the stored job's (services/jobs/).
#include <cstdint>
#include <optional>

namespace anchordb::storage {

struct ForgetPolicy {
  bool drop_superseded = true;                             // JSON "superseded_models"
  std::optional<double> keyframe_max_age_s = 7 * 86400.0;  // nullopt (JSON null): keyframes never expire
  double keep_relevance_at_least = 0.5;
  std::optional<double> event_max_age_s = 30 * 86400.0;    // nullopt (JSON null): events never expire
  bool vacuum = false;
};

struct ForgetRequest {
  ForgetPolicy policy;
  bool dry_run = false;
  // The clock ages are measured from (JSON "now": ns or ISO 8601, not in the future); default the wall clock. A
  // simulation or a replay of recorded data forgets by its own time.
  std::optional<std::int64_t> now_ns;
};

}  // namespace anchordb::storage
