#pragma once
// Long work as jobs (SPEC §3 "Jobs", §5 "long work returns 202 with a job"): persisted in the jobs table, run one at a
// time in submission order by one worker thread. Kinds are registered (services/jobs/job_registry.h); built in:
// "forget" (storage/forgetting.h) and "backup" (storage/backup.h: an online copy of the file; a kill leaves no copy
// under the final name, only a ".partial").
//
// - Submit validates synchronously: bad input throws (nothing is queued), an unknown map is 404, a full queue 503.
// - The forgetting transaction records the job's outcome in the same commit as the deletions, so a job is either
//   'succeeded' with its deletions or shows no deletion at all; a vacuum runs after that commit (stage "vacuum").
// - At start-up, jobs found 'queued' or 'running' (a kill -9 or a crash) are marked 'failed' with the error
//   "interrupted by a server stop"; their result (when the deletions were committed before a vacuum) is kept.
//   With several servers on one database (issue 31) a server runs the jobs it accepted, and only the jobs of a server
//   that is gone are marked (storage/server_presence.h: PostgreSQL itself says whether that server's session holds
//   its lock): at start-up, and by the worker every reap_interval_s for a server seen gone at two passes in a row (a
//   server that lost its session in a failover takes its lock again within one pass and keeps its jobs).
// - The destructor interrupts a running job (it rolls back, or its vacuum is cut short) and joins the worker.
// Progress (stage, fraction) of the running job is kept in memory while its transaction holds the write lock and
// overlaid on the stored row by Get.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "schema/clock.h"
#include "services/jobs/job_registry.h"
#include "services/jobs/job_types.h"
#include "storage/forget_policy.h"
#include "storage/job_repository.h"
#include "storage/server_presence.h"
#include "storage/connection.h"
#include "storage/store.h"

namespace anchordb::services {

struct JobSettings {
  int max_queued = 16;               // more queued jobs: 503
  int busy_timeout_ms = 30000;       // the job's own connection waits this long for the write lock
  std::string synchronous = "FULL";  // of the job's connection (as the store's)
  std::string backup_dir;            // where backups go; empty: backups are refused
  double reap_interval_s = 5.0;      // [s] how often the worker looks for the jobs of servers that are gone
};

class JobService {
 public:
  explicit JobService(storage::Store& store, JobSettings settings = {}, const Clock& clock = SystemClock::Instance());
  ~JobService();
  JobService(const JobService&) = delete;
  JobService& operator=(const JobService&) = delete;

  // Adds a kind (Error kConflict when its name is taken). Jobs of it may be submitted from then on.
  void Register(JobKind kind);

  // Queues a job of a registered kind with its request document. Unknown kind: kInvalidArgument ("kind"); the kind's
  // check throws on bad input; unknown map: kNotFound; a full queue or a stopping server: kOverloaded.
  JobTicket Submit(const std::string& kind, const std::optional<std::string>& map, const std::string& request_document);
  // A forgetting run over `map` (storage/forgetting.h). Ages negative or over 100 years, a relevance outside
  // [0, 1] or a `now` in the future: kUnprocessable naming "policy.<name>" or "now".
  JobTicket SubmitForget(const std::string& map, const storage::ForgetRequest& request);
  // An online copy of the whole database into settings.backup_dir; the job's request and result name the file.
  // A label that is not an id: kInvalidArgument ("label"); no backup_dir: kUnprocessable ("backup_dir").
  JobTicket SubmitBackup(const BackupRequest& request);
  // Unknown id: kNotFound.
  JobView Get(std::int64_t id);
  // Newest first: the jobs of `map` (every job when none; unknown map: kNotFound) with id < before_id (0: no bound),
  // limit in [1, 1000] (kInvalidArgument "limit"), the running one with its live stage and progress.
  std::vector<JobView> List(const std::optional<std::string>& map, std::int64_t before_id, int limit);
  // Stops a queued or running job: it fails with the error "cancelled" (a running one at its next progress report or
  // interrupted statement). False when the job had finished already; unknown id: kNotFound.
  bool Cancel(std::int64_t id);
  // The clock of the jobs' created_ns / updated_ns [ns since the Unix epoch].
  std::int64_t NowNs() const { return clock_.NowNs(); }
  // Jobs marked failed at start-up because a server stop interrupted them.
  int interrupted_at_start() const { return interrupted_at_start_; }
  // This server's id on the database (the jobs it accepts carry it).
  const std::string& server_id() const { return presence_->id(); }
  // Jobs of other servers found gone and marked failed since start (the worker's passes).
  int interrupted_since_start() const { return interrupted_since_start_.load(); }
  // Blocks until no job is queued or running (tests); false on timeout.
  bool WaitIdle(double timeout_s);

 private:
  class Context;
  // Reserves a queue slot, writes the queued row (map checked when given) and wakes the worker; returns its id.
  std::int64_t Enqueue(const std::string& kind, const std::optional<std::string>& map, const std::string& request_document);
  // A stored job as served (an unrecorded failure or the live progress applied). Needs mutex_.
  JobView ViewOf(const storage::JobRecord& r) const;
  void Worker();
  void RunJob(std::int64_t id);
  void Fail(std::int64_t id, const JobKind* kind, const std::string& what);
  // Writes the failures Fail could not write (the database refused writes then); keeps those that fail again.
  void RecordFailures();
  // Marks the unfinished jobs of servers that are gone: at once (start-up), or seen gone at the previous pass too.
  int MarkJobsOfGoneServers(bool at_once);
  void Reap();  // the worker's pass: Hold, then MarkJobsOfGoneServers(false); errors wait for the next pass
  void SetStatus(storage::Connection& c, std::int64_t id, JobStatus status, const std::string& stage, double progress,
                 const std::string* result_document, const std::string* error) const;

  storage::Store& store_;
  JobSettings settings_;
  const Clock& clock_;
  int interrupted_at_start_ = 0;
  std::atomic<int> interrupted_since_start_{0};
  std::unique_ptr<storage::ServerPresence> presence_;  // used by the constructor, then by the worker only
  std::set<std::optional<std::string>> gone_at_last_pass_;
  std::map<std::string, std::string> notes_after_result_;  // kind -> note, for jobs marked after their result
  std::mutex mutex_;
  JobRegistry registry_;  // guarded by mutex_
  std::condition_variable wake_;
  std::condition_variable idle_;
  bool stop_ = false;
  std::atomic<bool> interrupt_{false};  // the server stops
  std::atomic<bool> cancel_{false};     // the live job is cancelled
  int pending_ = 0;  // queued + running, as this process knows them
  int reserved_ = 0;  // submissions whose job row is being written (count against max_queued, not yet for the worker)
  std::int64_t live_id_ = 0;
  std::string live_stage_;
  double live_progress_ = 0.0;
  storage::Connection* live_connection_ = nullptr;  // interrupted on stop or cancel
  // Jobs that failed while the database refused to record it (id -> error): served as failed, never run again,
  // written when the worker next wakes (start-up marks them failed if the server stops first).
  std::map<std::int64_t, std::string> unrecorded_failures_;
  std::thread worker_;
};

}  // namespace anchordb::services
