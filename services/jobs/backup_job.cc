// The "backup" job kind and JobService::SubmitBackup (its stored request and report: storage/job_documents.h).
#include "services/jobs/backup_job.h"

#include <filesystem>

#include "schema/error.h"
#include "schema/ids.h"
#include "storage/backup.h"
#include "storage/job_documents.h"
#include "storage/connection.h"

namespace anchordb::services {
JobKind BackupJobKind(const std::string& db_path, const JobSettings& settings) {
  JobKind kind;
  kind.name = "backup";
  kind.first_stage = "copying";
  kind.check = [dir = settings.backup_dir](const JobSubmission& s) {
    if (dir.empty()) throw Error(ErrorCode::kUnprocessable, "this server has no backup_dir", "backup_dir");
    const std::filesystem::path file = storage::DecodeBackupRequest(s.request, "a backup request").file;
    if (std::filesystem::path(dir) / file.filename() != file) {
      throw Error(ErrorCode::kInvalidArgument, "a backup goes into the server's backup_dir", "file");
    }
  };
  kind.run = [db_path, timeout_ms = settings.busy_timeout_ms, synchronous = settings.synchronous](JobContext& job) -> std::optional<std::string> {
    const std::string file = storage::DecodeBackupRequest(job.request(), "job " + std::to_string(job.id()) + "'s request").file;
    const storage::BackupReport report = storage::Backup(db_path, file, timeout_ms, [&](double fraction) {
      job.Progress(0.95 * fraction);  // the integrity check and the sync come after the copy
    });
    // The job is recorded succeeded before it ends; when that write fails the copy is removed, so a failed backup
    // job never leaves a file (and its retry can take the same name).
    const std::string result = storage::EncodeBackupReport(report);
    try {
      storage::ConnectionOptions options;
      options.busy_timeout_ms = timeout_ms;
      options.synchronous = synchronous;
      const std::unique_ptr<storage::Connection> c = storage::OpenConnection(db_path, options);
      storage::Transaction tx(*c);
      job.Record(*c, JobStatus::kSucceeded, "done", 1.0, &result);
      tx.Commit();
    } catch (...) {
      std::error_code ec;
      std::filesystem::remove(file, ec);
      throw;
    }
    return std::nullopt;  // recorded
  };
  return kind;
}

JobTicket JobService::SubmitBackup(const BackupRequest& request) {
  if (!request.label.empty()) json::CheckId(request.label, "label");  // it becomes part of a file name
  if (settings_.backup_dir.empty()) throw Error(ErrorCode::kUnprocessable, "this server has no backup_dir", "backup_dir");
  const std::string file = storage::BackupFileName(settings_.backup_dir, store_.path(), clock_.NowNs(), request.label);
  return Submit("backup", std::nullopt, storage::EncodeBackupRequest({file}));
}

}  // namespace anchordb::services
