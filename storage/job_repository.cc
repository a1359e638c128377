#include "storage/job_repository.h"

#include <string>
#include <utility>

#include "schema/error.h"

namespace anchordb::storage {

namespace {
constexpr std::pair<JobStatus, const char*> kJobStatusNames[] = {
    {JobStatus::kQueued, "queued"}, {JobStatus::kRunning, "running"}, {JobStatus::kSucceeded, "succeeded"},
    {JobStatus::kFailed, "failed"}};
}  // namespace

const char* JobStatusName(JobStatus status) {
  for (const auto& [value, name] : kJobStatusNames) {
    if (value == status) return name;
  }
  throw Error(ErrorCode::kInternal, "unknown job status");
}

JobStatus JobStatusFromName(std::string_view name) {
  for (const auto& [value, stored] : kJobStatusNames) {
    if (name == stored) return value;
  }
  throw Error(ErrorCode::kInternal, "a stored job has the unknown status '" + std::string(name) + "'");
}

std::int64_t InsertJob(Connection& c, const std::string& kind, const std::optional<std::string>& map_id,
                       const std::string& request_document, std::int64_t now_ns, const std::string& server_id) {
  Statement s(c, "INSERT INTO jobs (kind, map_id, status, stage, progress, request, request_document, created_ns, "
                 "updated_ns, server_id) VALUES (?, ?, 'queued', '', 0, '', ?, ?, ?, ?) RETURNING id");
  s.Bind(1, kind);
  if (map_id) s.Bind(2, *map_id);
  else s.BindNull(2);
  s.BindBlob(3, request_document).Bind(4, now_ns).Bind(5, now_ns).Bind(6, server_id);
  return s.RunReturningId();
}

namespace {

constexpr const char* kJobColumns =
    "SELECT id, kind, map_id, status, stage, progress, request, result, error, created_ns, updated_ns, "
    "request_document, result_document FROM jobs";

JobRecord ReadJob(Statement& s) {
  JobRecord r;
  r.id = s.Int(0);
  r.kind = s.Text(1);
  if (!s.IsNull(2)) r.map_id = s.Text(2);
  r.status = JobStatusFromName(s.Text(3));
  r.stage = s.Text(4);
  r.progress = s.Double(5);
  // Migration 0024: a row has its document encoded, or the JSON text an earlier version wrote.
  if (!s.IsNull(11)) r.request.encoded = s.Blob(11);
  else r.request.legacy_json = s.Text(6);
  if (!s.IsNull(12)) r.result = StoredDocument{s.Blob(12), {}};
  else if (!s.IsNull(7)) r.result = StoredDocument{{}, s.Text(7)};
  if (!s.IsNull(8)) r.error = s.Text(8);
  r.created_ns = s.Int(9);
  r.updated_ns = s.Int(10);
  return r;
}

}  // namespace

std::optional<JobRecord> FindJob(Connection& c, std::int64_t id) {
  Statement s(c, std::string(kJobColumns) + " WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return ReadJob(s);
}

std::vector<JobRecord> ListJobs(Connection& c, const std::optional<std::string>& map_id, std::int64_t before_id, int limit) {
  std::string sql = std::string(kJobColumns) + " WHERE (?1 = 0 OR id < ?1)";
  if (map_id) sql += " AND map_id = ?2";
  sql += " ORDER BY id DESC LIMIT ?3";
  Statement s(c, sql);
  s.Bind(1, before_id).Bind(3, static_cast<std::int64_t>(limit));
  if (map_id) s.Bind(2, *map_id);
  std::vector<JobRecord> out;
  while (s.Step()) out.push_back(ReadJob(s));
  return out;
}

std::optional<std::int64_t> NextQueuedJob(Connection& c, const std::string& server_id, std::int64_t after_id) {
  Statement s(c, "SELECT id FROM jobs WHERE status = 'queued' AND server_id = ? AND id > ? ORDER BY id LIMIT 1");
  s.Bind(1, server_id).Bind(2, after_id);
  if (!s.Step()) return std::nullopt;
  return s.Int(0);
}

void SetJobStatus(Connection& c, std::int64_t id, JobStatus status, const std::string& stage, double progress,
                  const std::string* result_document, const std::string* error, std::int64_t now_ns) {
  Statement s(c, "UPDATE jobs SET status = ?, stage = ?, progress = ?, result_document = coalesce(?, result_document), "
                 "error = ?, updated_ns = ? WHERE id = ?");
  s.Bind(1, std::string_view(JobStatusName(status))).Bind(2, stage).Bind(3, progress);
  if (result_document) s.BindBlob(4, *result_document);
  else s.BindNull(4);
  if (error) s.Bind(5, *error);
  else s.BindNull(5);
  s.Bind(6, now_ns).Bind(7, id).Run();
}

std::vector<std::optional<std::string>> UnfinishedJobServers(Connection& c) {
  Statement s(c, "SELECT server_id FROM jobs WHERE status IN ('queued', 'running') GROUP BY server_id "
                 "ORDER BY server_id IS NOT NULL, server_id");  // none first on both engines
  std::vector<std::optional<std::string>> out;
  while (s.Step()) out.push_back(s.IsNull(0) ? std::nullopt : std::optional<std::string>(s.Text(0)));
  return out;
}

int MarkUnfinishedJobsFailed(Connection& c, const std::optional<std::string>& server_id, const std::string& message,
                             std::int64_t now_ns, const std::map<std::string, std::string>& notes_after_result) {
  const std::string set = std::string("UPDATE jobs SET status = 'failed', error = ?1 || CASE WHEN stage <> '' THEN ' (stage ' || "
                                      "stage || ')' ELSE '' END || ?3, updated_ns = ?2 WHERE status IN ('queued', 'running') AND ") +
                          (server_id ? "server_id = ?5" : "server_id IS NULL");
  const auto bind_server = [&](Statement& s) {
    if (server_id) s.Bind(5, *server_id);
  };
  int changed = 0;
  for (const auto& [kind, note] : notes_after_result) {
    Statement s(c, set + " AND kind = ?4 AND (result IS NOT NULL OR result_document IS NOT NULL)");
    s.Bind(1, message).Bind(2, now_ns).Bind(3, note).Bind(4, kind);
    bind_server(s);
    s.Run();
    changed += static_cast<int>(c.Changes());
  }
  Statement s(c, set);  // ?4 unused: SQLite ignores the gap, storage/postgres.cc declares it text
  s.Bind(1, message).Bind(2, now_ns).Bind(3, std::string());
  bind_server(s);
  s.Run();
  return changed + static_cast<int>(c.Changes());
}

}  // namespace anchordb::storage
