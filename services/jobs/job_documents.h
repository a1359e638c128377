#pragma once
// The stored documents of the built-in jobs: a forget job's request (its policy) and report, a backup job's request
// (the file it writes) and report. Typed records encoded by storage's codecs (storage/job_documents.h: the blob
// envelope with a kind and a version); their JSON is written only in api/ (api/job_json.h), also for the CLI.
#include "storage/job_documents.h"

namespace anchordb::services {

using storage::BackupJobRequest;
using storage::DecodeBackupReport;
using storage::DecodeBackupRequest;
using storage::DecodeForgetReport;
using storage::DecodeForgetRequest;
using storage::EncodeBackupReport;
using storage::EncodeBackupRequest;
using storage::EncodeForgetReport;
using storage::EncodeForgetRequest;

}  // namespace anchordb::services
