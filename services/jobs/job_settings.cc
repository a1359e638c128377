#include "services/jobs/job_settings.h"

namespace anchordb::services {

void BindJobSettings(SettingsBinder& b, JobSettings& j) {
  b.Bind("job_max_queued", "jobs (forgetting, backups) that may wait; one more is refused with 503", &j.max_queued, 1, 10000);
  b.Bind("job_busy_timeout_ms", "how long a job's connection waits for the write lock [ms]", &j.busy_timeout_ms, 0, 3.6e6);
}

}  // namespace anchordb::services
