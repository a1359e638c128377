#include "services/jobs/job_settings.h"

namespace anchordb::services {

void BindJobSettings(SettingsBinder& b, JobSettings& j) {
  b.Bind("job_max_queued", "jobs (forgetting, backups) that may wait; one more is refused with 503", &j.max_queued, 1, 10000);
  b.Bind("job_busy_timeout_ms", "how long a job's connection waits for the write lock [ms]", &j.busy_timeout_ms, 0, 3.6e6);
  b.Bind("job_reap_interval_s", "how often a server marks interrupted the jobs of another server on the same database "
         "that is gone (seen gone at two passes in a row) [s]", &j.reap_interval_s, 0.05, 3600.0);
}

}  // namespace anchordb::services
