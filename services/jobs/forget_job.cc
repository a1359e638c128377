// The "forget" job kind and JobService::SubmitForget (its stored request and report: storage/job_documents.h).
#include "services/jobs/forget_job.h"

#include "engine/forgetting/keep_rules.h"
#include "schema/error.h"
#include "storage/forgetting.h"
#include "storage/job_documents.h"

namespace anchordb::services {
namespace {

constexpr double kMaxAgeS = 100.0 * 365.25 * 86400.0;  // keeps now - age representable in int64 nanoseconds

void CheckAge(const std::optional<double>& age_s, const std::string& field) {
  if (!age_s) return;
  if (!(*age_s >= 0.0)) throw Error(ErrorCode::kUnprocessable, field + " must not be negative (seconds)", field);
  if (*age_s > kMaxAgeS) throw Error(ErrorCode::kUnprocessable, field + " must be at most 100 years in seconds", field);
}

std::optional<std::string> RunForget(JobContext& job, const std::string& db_path, const JobSettings& settings) {
  const storage::ForgetRequest request =
      storage::DecodeForgetRequest(job.request(), "job " + std::to_string(job.id()) + "'s request");
  storage::ConnectionOptions options;
  options.busy_timeout_ms = settings.busy_timeout_ms;
  options.synchronous = settings.synchronous;
  const std::unique_ptr<storage::Connection> owned_connection = storage::OpenConnection(db_path, options);
  storage::Connection& connection = *owned_connection;
  InterruptibleScope interruptible(job, connection);
  const auto progress = [&](std::string_view stage, double fraction) { job.Progress(stage, fraction); };
  const auto before_commit = [&](storage::Connection& c, const storage::ForgetReport& report) {
    // Recorded with the deletions: a kill after this commit finds the job done (or, with a vacuum still to run,
    // 'running' in stage vacuum with the committed result, which start-up marks failed/interrupted).
    const std::string result = storage::EncodeForgetReport(report);
    if (request.policy.vacuum) job.Record(c, JobStatus::kRunning, "vacuum", 0.9, &result);
    else job.Record(c, JobStatus::kSucceeded, "done", 1.0, &result);
  };
  const storage::ForgetReport report = storage::Forget(connection, job.map().value_or(""), request.policy,
                                                       ForgetKeepRules(), request.now_ns.value_or(job.NowNs()),
                                                       request.dry_run, progress, before_commit);
  if (request.dry_run || request.policy.vacuum) return storage::EncodeForgetReport(report);
  return std::nullopt;  // recorded with the deletions
}

}  // namespace

storage::ForgetRules ForgetKeepRules() {
  return {[](const OldEventFacts& e) { return engine::forgetting::KeepEvent(e); },
          [](const OldKeyframeFacts& k, double keep_relevance_at_least) {
            return engine::forgetting::KeepKeyframe(k, keep_relevance_at_least);
          }};
}

void CheckForgetRequest(const storage::ForgetRequest& request, std::int64_t wall_now_ns) {
  if (request.now_ns && *request.now_ns > wall_now_ns) {
    throw Error(ErrorCode::kUnprocessable, "now must not lie in the future", "now");
  }
  CheckAge(request.policy.keyframe_max_age_s, "policy.keyframe_max_age_s");
  CheckAge(request.policy.event_max_age_s, "policy.event_max_age_s");
  const double relevance = request.policy.keep_relevance_at_least;
  if (!(relevance >= 0.0 && relevance <= 1.0)) {
    throw Error(ErrorCode::kUnprocessable, "policy.keep_relevance_at_least must be in [0, 1]", "policy.keep_relevance_at_least");
  }
}

JobKind ForgetJobKind(const std::string& db_path, const JobSettings& settings) {
  JobKind kind;
  kind.name = "forget";
  kind.first_stage = "forgetting";
  kind.needs_map = true;
  kind.check = [](const JobSubmission& s) { CheckForgetRequest(storage::DecodeForgetRequest(s.request, "a forget request"), s.now_ns); };
  kind.run = [db_path, settings](JobContext& job) { return RunForget(job, db_path, settings); };
  kind.note_when_failed_after_result = " (after the deletions were committed: see result)";
  return kind;
}

JobTicket JobService::SubmitForget(const std::string& map, const storage::ForgetRequest& request) {
  return Submit("forget", map, storage::EncodeForgetRequest(request));
}

}  // namespace anchordb::services
