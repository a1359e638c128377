#pragma once
// The durable, per-map first-in-first-out queue of keyframe change analyses (thesis 3.3.4; SPEC §8).
//
// The scene service inserts a queue row (storage/analysis_queue.h) in the transaction that stores a keyframe and
// answers without waiting. Worker threads (`threads`, default 1, and as many catch-up workers, below) take the
// oldest row of a map whose analysis is not running, load the keyframe as stored (LoadKeyframeNotice), run EventService::AnalyseKeyframe and delete the row in
// the transaction that writes the events. One map's keyframes are analysed one at a time in keyframe order (action
// layers chain keyframe to keyframe); different maps run in parallel (a map behind and one that is not, or several
// maps when threads > 1). No scene-model lock is taken,
// so reads and frames of a model never wait for its analysis.
//
// - Rows left by a stop or kill -9 are found by the workers at start (Start), so an acknowledged keyframe is analysed.
// - A failed attempt is recorded in the row (attempts, last_error) and retried after a backoff that doubles from
//   `retry_initial_s` up to `retry_max_s`; later keyframes of that map wait for it (order). Transient failures
//   (kUnavailable, kInsufficientStorage: the disk failed or is full, memory ran out) retry without end; others are
//   given up after `max_attempts` (the row stays, marked failed, and the map's queue moves on).
// - A keyframe deleted before its analysis (forgetting, its scene or map deleted) takes its row with it; the analysis
//   is skipped.
// - The workers run at a lower CPU priority (`nice`, and never above the niceness of the thread that started
//   them): on a busy machine the requests go first and the queue grows, to be worked off when the load drops.
// - A map's backlog is bounded (`backlog`, engine/events/analysis_backlog.h; only with started workers, in-process
//   callers run the queue themselves). From `catch_up_at` pending analyses on (and `nice` > 0), the map's analyses
//   are run by catch-up workers (as many as `threads`) at the requests' priority; the analysis a nice worker is
//   running then is raised to it too where the process may lower a niceness (root, CAP_SYS_NICE or RLIMIT_NICE),
//   elsewhere it ends at its own. From `max_pending` on, the map's new frames and manual keyframes are refused
//   (Admit: kOverloaded, 503 with Retry-After, nothing stored; counted in /metrics) until it is below again. The
//   bound is checked before a frame is applied, so frames of several scene models of the map let through at once,
//   and closes (never refused), can take it a little past max_pending. A map whose oldest analysis keeps failing
//   transiently (retried without end) stays refused for that long.
// - Await waits (at most `wait_max_s`) for one keyframe's analysis; without started workers it runs the queue in the
//   caller first. Drain runs every due analysis in the caller, for deterministic in-process callers (tests,
//   evaluations). The server starts the workers (Start); in-process users that do not, run analyses only through
//   Await and Drain.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "engine/events/analysis_backlog.h"
#include "schema/clock.h"
#include "services/events/event_service.h"
#include "services/scene/keyframe_listener.h"
#include "storage/analysis_queue.h"
#include "storage/store.h"

namespace anchordb::services {

struct AnalysisQueueSettings {
  int threads = 1;               // worker threads; 0: none (in-process callers Drain)
  double wait_max_s = 30.0;      // bound of Await (wait_for_analysis) [s]
  double retry_initial_s = 0.5;  // backoff after the first failed attempt [s], doubling
  double retry_max_s = 60.0;     // longest backoff [s]
  int max_attempts = 8;          // non-transient failures before an analysis is given up
  int nice = 10;                 // the workers' scheduling niceness (0: as the request threads; 19: lowest)
  engine::AnalysisBacklogLimits backlog;  // per map: catch-up at request priority, then refused frames
};

// One map's queue (or all maps'), for GET /v1/maps/{map}/analysis.
struct AnalysisQueueView {
  std::int64_t pending = 0;                    // queued or running
  std::int64_t running = 0;                    // of them, being analysed now
  std::int64_t failed = 0;                     // given up
  std::int64_t retrying = 0;                   // pending after at least one failed attempt
  std::optional<double> oldest_pending_age_s;  // since the oldest pending keyframe was stored
  std::vector<storage::QueuedAnalysis> failures;  // rows with failed attempts, oldest first
};

// Process-wide counters since start (GET /metrics).
struct AnalysisCounters {
  std::int64_t enqueued = 0, done = 0, skipped = 0, failed_attempts = 0, given_up = 0;
  double busy_s = 0.0;  // time spent analysing [s]
  std::int64_t computed_in_write = 0;  // analyses computed inside their write transaction (EventService)
  std::int64_t frames_refused = 0;     // frames and manual keyframes refused for a map's backlog (Admit)
  std::int64_t caught_up = 0;          // analyses run by the catch-up workers (at request priority)
  std::int64_t raised = 0;             // running analyses of a nice worker raised to request priority
};

class AnalysisQueue : public KeyframeListener {
 public:
  AnalysisQueue(storage::Store& store, EventService& events, AnalysisQueueSettings settings,
                const Clock& clock = SystemClock::Instance());
  ~AnalysisQueue() override;  // stops and joins the workers (a running analysis finishes first)
  AnalysisQueue(const AnalysisQueue&) = delete;
  AnalysisQueue& operator=(const AnalysisQueue&) = delete;

  // Starts settings.threads workers and as many catch-up workers (no-op when running or threads == 0); they resume
  // rows found in the database.
  void Start();
  void Stop();

  void Admit(const std::string& map) override;
  void Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) override;
  void Enqueued(const std::string& map) override;
  KeyframeAnalysisStatus Await(std::int64_t keyframe_id) override;

  // Runs every analysis due now in the calling thread (and waits for those running elsewhere) until none is due;
  // `ignore_backoff` also runs those waiting for a retry. Returns how many this call ran.
  int Drain(bool ignore_backoff = false);

  // One map's queue (kNotFound when the map does not exist), or every map's (nullopt).
  AnalysisQueueView View(const std::optional<std::string>& map);
  AnalysisCounters counters() const;
  const AnalysisQueueSettings& settings() const { return settings_; }

  // Tests only: runs in the analysing thread after a row was taken, before its keyframe is read.
  void SetRunHookForTesting(std::function<void(const storage::QueuedAnalysis&)> hook) { run_hook_ = std::move(hook); }

 private:
  // Which maps a worker takes: any (in-process callers, or no catch-up), those below the catch-up threshold (the
  // workers at `nice`), those at or above it (the catch-up workers, at the requests' priority).
  enum class Role { kAny, kBackground, kCatchUp };
  // The oldest due row of a map not running now (the head of its map's queue, not in `exclude`, of a map `role`
  // takes), marked running; nullopt: none. `seen`: the generation the answer is current for.
  std::optional<storage::QueuedAnalysis> Take(bool ignore_backoff, const std::set<std::int64_t>& exclude, std::uint64_t* seen,
                                              Role role = Role::kAny);
  void Run(const storage::QueuedAnalysis& row);
  void Finish(const storage::QueuedAnalysis& row, KeyframeAnalysisStatus status);
  void Worker(Role role);
  // A map `catch_up_at` behind whose analysis a nice worker runs: that thread is raised to request priority (when the
  // process may).
  void RaiseIfBehind(const std::string& map);
  // The map's analyses not given up, read in one statement.
  std::int64_t Pending(const std::string& map);
  std::int64_t BackoffNs(int attempts) const;

  storage::Store& store_;
  EventService& events_;
  AnalysisQueueSettings settings_;
  const Clock& clock_;
  std::function<void(const storage::QueuedAnalysis&)> run_hook_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;  // a row was queued or finished, or stopping
  std::uint64_t generation_ = 0;     // increases with every change
  std::uint64_t finished_ = 0;       // increases with every finished attempt
  bool stopping_ = false;
  std::set<std::string> running_maps_;
  std::map<std::string, std::int64_t> nice_runs_;  // map -> thread id of the nice worker running its analysis
  int request_nice_ = 0;                           // the niceness of the thread that started the workers
  int background_nice_ = 0;                        // the nice workers': max(nice, request_nice_)
  std::map<std::int64_t, std::int64_t> not_before_ns_;  // backoff kept in memory when the failure could not be written
  // Outcomes of recent analyses, for Await (bounded: the oldest are dropped).
  std::map<std::int64_t, KeyframeAnalysisStatus> outcomes_;
  std::deque<std::int64_t> outcome_order_;
  AnalysisCounters counters_;
  std::vector<std::thread> workers_;
};

}  // namespace anchordb::services
