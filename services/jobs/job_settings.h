#pragma once
// The settings of the job queue, bound once to JobSettings (its synchronous mode and backup directory come from the
// server's storage settings).
#include "schema/settings.h"
#include "services/jobs/job_service.h"

namespace anchordb::services {

void BindJobSettings(SettingsBinder& b, JobSettings& jobs);

}  // namespace anchordb::services
