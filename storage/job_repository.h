#pragma once
// SQL for jobs (migration 0004): long work with status, stage, progress, result and error.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"
#include "storage/document_codec.h"
#include "storage/job_status.h"

namespace anchordb::storage {

struct JobRecord {
  std::int64_t id = 0;
  std::string kind;
  std::optional<std::string> map_id;
  JobStatus status = JobStatus::kQueued;
  std::string stage;
  double progress = 0.0;
  StoredDocument request;                // the kind's request (storage/document_codec.h)
  std::optional<StoredDocument> result;  // none until a result is recorded
  std::optional<std::string> error;
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
};

// map_id: the map the job works on, or none (a backup of the whole file); server_id: the server that accepted it
// and runs it (storage/server_presence.h).
std::int64_t InsertJob(Connection& c, const std::string& kind, const std::optional<std::string>& map_id,
                       const std::string& request_document, std::int64_t now_ns, const std::string& server_id);
std::optional<JobRecord> FindJob(Connection& c, std::int64_t id);
// Newest first: jobs of `map_id` (every job when none) with id < before_id (no bound when 0), at most `limit`.
std::vector<JobRecord> ListJobs(Connection& c, const std::optional<std::string>& map_id, std::int64_t before_id, int limit);
// The oldest queued job `server_id` accepted (a server runs the jobs it accepted).
std::optional<std::int64_t> NextQueuedJob(Connection& c, const std::string& server_id, std::int64_t after_id = 0);
// result_document (encoded): kept as stored when null; error: replaced (null clears it).
void SetJobStatus(Connection& c, std::int64_t id, JobStatus status, const std::string& stage, double progress,
                  const std::string* result_document, const std::string* error, std::int64_t now_ns);
// The servers holding queued or running jobs (nullopt: rows written before migration 0030, nobody's).
std::vector<std::optional<std::string>> UnfinishedJobServers(Connection& c);
// Jobs of `server_id` (nullopt: of no server) left queued or running (by a stop or a crash) become failed with
// `message` and their stage; a job that had recorded a result (its work was committed before the stop) also gets
// the note of its kind from `notes_after_result` (by kind name). Returns how many.
int MarkUnfinishedJobsFailed(Connection& c, const std::optional<std::string>& server_id, const std::string& message,
                             std::int64_t now_ns, const std::map<std::string, std::string>& notes_after_result = {});

}  // namespace anchordb::storage
