#pragma once
// Typed requests and results of JobService. A job's request and result are each kind's own typed documents, encoded
// by its storage codec (storage/document_codec.h); JobService passes them through without knowing the kind, and the
// HTTP edge writes each kind's JSON (api/job_json.h).
#include <cstdint>
#include <optional>
#include <string>

#include "storage/document_codec.h"
#include "storage/forget_policy.h"
#include "storage/job_documents.h"  // the built-in kinds' documents
#include "storage/job_status.h"

namespace anchordb::services {

// What a forgetting job is asked (the policy is the store's: storage/forget_policy.h).
using ForgetPolicy = storage::ForgetPolicy;
using ForgetRequest = storage::ForgetRequest;

// A job's status and its one table of names (storage/job_status.h): "queued", "running", "succeeded", "failed", as
// stored and served.
using JobStatus = storage::JobStatus;
inline const char* JobStatusId(JobStatus status) { return storage::JobStatusName(status); }

// An online copy of the whole database into the server's backup_dir (storage/backup.h).
struct BackupRequest {
  std::string label;  // empty, or an id (1-64 of [A-Za-z0-9_.-]) that becomes part of the file name
};

// A job's request or result as stored: encoded, or the JSON text of a row written before migration 0024.
using JobDocument = storage::StoredDocument;

// A job just queued.
struct JobTicket {
  std::int64_t job = 0;
  std::string kind;
  std::optional<std::string> map;  // none for jobs over the whole file (backups)
  JobDocument request;             // the request as stored
};

struct JobView {
  std::int64_t id = 0;
  std::string kind;
  std::optional<std::string> map;
  JobStatus status = JobStatus::kQueued;
  std::string stage;
  double progress = 0.0;  // [0, 1]; of the running job, the live value
  JobDocument request;
  std::optional<JobDocument> result;
  std::optional<std::string> error;
  std::int64_t created_ns = 0, updated_ns = 0;
};

}  // namespace anchordb::services
