#pragma once
// The "backup" job kind: an online copy of the whole database file (storage/backup.h) into the backup directory.
#include <string>

#include "services/jobs/job_registry.h"
#include "services/jobs/job_service.h"

namespace anchordb::services {

// The kind as JobService registers it: copies `db_path` into settings.backup_dir (a submission naming a file
// elsewhere, or a server without backup_dir, is refused).
JobKind BackupJobKind(const std::string& db_path, const JobSettings& settings);

}  // namespace anchordb::services
