#pragma once
// The stored documents of the jobs table that outlive their job's run: a forget job's request (its policy), a
// backup job's request (the file it writes), and the reports of a forgetting run and of a backup (job results; the
// CLI prints and audits the same text).
// They are serialised JSON today, built in job_documents.cc; issue 30 turns job requests and results into typed
// records with storage codecs, and this file is where that happens.
#include <string>

#include "storage/backup.h"
#include "storage/forget_policy.h"
#include "storage/forgetting.h"

namespace anchordb::services {

std::string ForgetRequestDocument(const storage::ForgetRequest& request);
// Error(kInvalidArgument, field "request") when `text` is not a forget job's request.
storage::ForgetRequest ForgetRequestFromDocument(const std::string& text);
std::string ForgetReportDocument(const storage::ForgetReport& report);
std::string BackupReportDocument(const storage::BackupReport& report);
// {"file": path}; Error(kInvalidArgument, field "file") when `text` names no file.
std::string BackupRequestDocument(const std::string& file);
std::string BackupFileFromDocument(const std::string& text);

}  // namespace anchordb::services
