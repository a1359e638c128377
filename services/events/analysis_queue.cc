#include "services/events/analysis_queue.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "schema/error.h"
#include "services/common/require.h"

namespace anchordb::services {
namespace {

constexpr std::size_t kKeptOutcomes = 4096;  // recent outcomes Await can still return with their events
constexpr auto kIdlePoll = std::chrono::milliseconds(500);  // a worker looks again for due retries at least this often

bool Transient(ErrorCode code) { return code == ErrorCode::kUnavailable || code == ErrorCode::kInsufficientStorage; }

KeyframeAnalysisStatus StatusOf(AnalysisState state, std::int64_t keyframe_id) {
  KeyframeAnalysisStatus s;
  s.state = state;
  s.keyframe_id = keyframe_id;
  return s;
}

}  // namespace

AnalysisQueue::AnalysisQueue(storage::Store& store, EventService& events, AnalysisQueueSettings settings, const Clock& clock)
    : store_(store), events_(events), settings_(settings), clock_(clock) {}

AnalysisQueue::~AnalysisQueue() { Stop(); }

void AnalysisQueue::Start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!workers_.empty()) return;
  // Catch-up workers only when the others run below the requests' priority; they keep this thread's niceness.
  const bool catch_up = settings_.nice > 0 && settings_.backlog.catch_up_at > 0;
  errno = 0;
  const int nice_now = getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
  request_nice_ = errno == 0 ? nice_now : 0;
  background_nice_ = std::max(settings_.nice, request_nice_);
  for (int i = 0; i < settings_.threads; ++i) {
    workers_.emplace_back([this, catch_up] { Worker(catch_up ? Role::kBackground : Role::kAny); });
    if (catch_up) workers_.emplace_back([this] { Worker(Role::kCatchUp); });
  }
}

void AnalysisQueue::Stop() {
  std::vector<std::thread> workers;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    workers.swap(workers_);
  }
  changed_.notify_all();
  for (auto& t : workers) t.join();
  std::lock_guard<std::mutex> lock(mutex_);
  stopping_ = false;
}

std::int64_t AnalysisQueue::Pending(const std::string& map) {
  return store_.ReadOneStatement([&](storage::Connection& c) { return storage::PendingAnalyses(c, map); });
}

void AnalysisQueue::Admit(const std::string& map) {
  if (settings_.backlog.max_pending <= 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (workers_.empty()) return;  // in-process callers run the queue themselves (Drain, Await)
  }
  const std::int64_t pending = Pending(map);
  if (!engine::RefusesFrames(settings_.backlog, pending)) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.frames_refused;
  }
  throw Error(ErrorCode::kOverloaded,
              "map '" + map + "' has " + std::to_string(pending) + " keyframe analyses pending (analysis_max_pending " +
                  std::to_string(settings_.backlog.max_pending) +
                  "): its frames and keyframes are refused until they catch up; retry after Retry-After");
}

void AnalysisQueue::Enqueue(storage::Connection& c, const QueuedKeyframe& k) {
  storage::QueuedAnalysis row;
  row.keyframe_id = k.keyframe_id;
  row.map_id = k.map;
  row.scene_id = k.scene_id;
  row.enqueued_ns = k.enqueued_ns;
  storage::EnqueueAnalysis(c, row);
}

void AnalysisQueue::Enqueued(const std::string& map) {
  bool nice_run;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++generation_;
    ++counters_.enqueued;
    nice_run = nice_runs_.count(map) > 0;
  }
  changed_.notify_all();
  if (nice_run) RaiseIfBehind(map);
}

void AnalysisQueue::RaiseIfBehind(const std::string& map) {
  std::int64_t pending = 0;
  try {
    pending = Pending(map);
  } catch (const std::exception&) {
    return;  // the store fails now: the running analysis keeps its priority
  }
  if (!engine::NeedsCatchUp(settings_.backlog, pending)) return;
  std::lock_guard<std::mutex> lock(mutex_);  // the worker leaves nice_runs_ under this lock before it renices itself
  const auto run = nice_runs_.find(map);
  if (run == nice_runs_.end()) return;
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(run->second), request_nice_) == 0) ++counters_.raised;
  nice_runs_.erase(run);  // raised once (or not permitted: not tried again)
}

std::int64_t AnalysisQueue::BackoffNs(int attempts) const {
  const double s = std::min(settings_.retry_max_s, settings_.retry_initial_s * std::pow(2.0, std::max(0, attempts - 1)));
  return static_cast<std::int64_t>(s * 1e9);
}

std::optional<storage::QueuedAnalysis> AnalysisQueue::Take(bool ignore_backoff, const std::set<std::int64_t>& exclude,
                                                           std::uint64_t* seen, Role role) {
  for (;;) {
    std::uint64_t before;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      before = finished_;
    }
    const std::vector<storage::QueueHead> heads = store_.Read([](storage::Connection& c) { return storage::QueueHeads(c); });
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_ != before) continue;  // an analysis finished meanwhile: the heads may be stale
    if (seen) *seen = generation_;
    const std::int64_t now = clock_.NowNs();
    for (const auto& [h, map_pending] : heads) {
      if (running_maps_.count(h.map_id) || exclude.count(h.keyframe_id)) continue;
      const bool behind = engine::NeedsCatchUp(settings_.backlog, map_pending);
      if ((role == Role::kBackground && behind) || (role == Role::kCatchUp && !behind)) continue;
      const auto memory = not_before_ns_.find(h.keyframe_id);
      const std::int64_t due = std::max(h.next_attempt_ns, memory == not_before_ns_.end() ? 0 : memory->second);
      if (!ignore_backoff && due > now) continue;  // this map waits for its head's retry
      running_maps_.insert(h.map_id);
      return h;
    }
    return std::nullopt;
  }
}

void AnalysisQueue::Run(const storage::QueuedAnalysis& row) {
  const auto started = std::chrono::steady_clock::now();
  KeyframeAnalysisStatus status = StatusOf(AnalysisState::kPending, row.keyframe_id);
  std::optional<std::string> error;
  bool transient = false;
  try {
    if (run_hook_) run_hook_(row);
    const auto notice = store_.Read([&](storage::Connection& c) { return LoadKeyframeNotice(c, row.map_id, row.keyframe_id); });
    const auto claim = [&](storage::Connection& c) { return storage::DequeueAnalysis(c, row.keyframe_id); };
    std::optional<KeyframeAnalysis> result;
    if (notice) result = events_.AnalyseKeyframe(*notice, claim);
    else store_.Write(claim);  // the keyframe is gone (its row normally went with it)
    status.state = result ? AnalysisState::kDone : AnalysisState::kSkipped;
    status.result = std::move(result);
  } catch (const Error& e) {
    error = e.what();
    transient = Transient(e.code());
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (error) {
    status.attempts = row.attempts + 1;
    status.last_error = *error;
    const bool give_up = !transient && status.attempts >= settings_.max_attempts;
    const std::int64_t next = clock_.NowNs() + BackoffNs(status.attempts);
    if (give_up) status.state = AnalysisState::kFailed;
    try {
      store_.Write([&](storage::Connection& c) { storage::RecordAnalysisFailure(c, row.keyframe_id, *error, next, give_up); });
    } catch (const std::exception&) {
      // The failure could not be written (the store fails now): the backoff is kept in memory below; the row's
      // attempts are counted again by the next failure.
      if (give_up) status.state = AnalysisState::kPending;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    not_before_ns_[row.keyframe_id] = next;
    ++counters_.failed_attempts;
    if (status.state == AnalysisState::kFailed) ++counters_.given_up;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    counters_.busy_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  Finish(row, std::move(status));
}

void AnalysisQueue::Finish(const storage::QueuedAnalysis& row, KeyframeAnalysisStatus status) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    running_maps_.erase(row.map_id);
    if (status.state == AnalysisState::kDone) ++counters_.done;
    if (status.state == AnalysisState::kSkipped) ++counters_.skipped;
    if (status.state != AnalysisState::kPending) not_before_ns_.erase(row.keyframe_id);
    auto [it, inserted] = outcomes_.emplace(row.keyframe_id, status);
    if (inserted) {
      outcome_order_.push_back(row.keyframe_id);
      if (outcome_order_.size() > kKeptOutcomes) {
        outcomes_.erase(outcome_order_.front());
        outcome_order_.pop_front();
      }
    } else if (it->second.state != AnalysisState::kDone) {
      it->second = std::move(status);  // a later attempt; a done outcome stays
    }
    ++generation_;
    ++finished_;
  }
  changed_.notify_all();
}

void AnalysisQueue::Worker(Role role) {
  const std::int64_t tid = syscall(SYS_gettid);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_) return;
    }
    // Linux applies a thread's niceness to that thread alone (its tid as the "process"), and going back to a higher
    // niceness needs no privilege: set again before each analysis, after a RaiseIfBehind. Failing is harmless.
    if (settings_.nice > 0 && role != Role::kCatchUp) (void)setpriority(PRIO_PROCESS, static_cast<id_t>(tid), background_nice_);
    std::uint64_t seen = 0;
    bool unreadable = false;
    try {
      if (auto row = Take(false, {}, &seen, role)) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          if (role == Role::kCatchUp) ++counters_.caught_up;
          if (role == Role::kBackground) nice_runs_[row->map_id] = tid;
        }
        Run(*row);
        if (role == Role::kBackground) {
          std::lock_guard<std::mutex> lock(mutex_);
          const auto mine = nice_runs_.find(row->map_id);  // another worker may have taken the map's next row by now
          if (mine != nice_runs_.end() && mine->second == tid) nice_runs_.erase(mine);
        }
        continue;
      }
    } catch (const std::exception&) {
      unreadable = true;  // the queue could not be read (the store fails now): look again after the idle poll
    }
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, kIdlePoll, [&] { return stopping_ || (!unreadable && generation_ != seen); });
  }
}

int AnalysisQueue::Drain(bool ignore_backoff) {
  int ran = 0;
  std::set<std::int64_t> attempted;  // each keyframe at most once per call: a failing one does not loop
  for (;;) {
    std::uint64_t seen = 0;
    if (auto row = Take(ignore_backoff, attempted, &seen)) {
      attempted.insert(row->keyframe_id);
      Run(*row);
      ++ran;
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    if (running_maps_.empty() && generation_ == seen) return ran;
    changed_.wait(lock, [&] { return generation_ != seen; });  // another thread's analysis finishes
  }
}

KeyframeAnalysisStatus AnalysisQueue::Await(std::int64_t keyframe_id) {
  bool no_workers;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    no_workers = workers_.empty();
  }
  if (no_workers) Drain();  // not started (in-process callers) or threads = 0: the caller runs the queue
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(settings_.wait_max_s);
  std::unique_lock<std::mutex> lock(mutex_);
  bool looked_up = false;
  for (;;) {
    const auto it = outcomes_.find(keyframe_id);
    if (it != outcomes_.end() && it->second.state != AnalysisState::kPending) return it->second;
    if (!looked_up) {
      lock.unlock();
      const auto row = store_.Read([&](storage::Connection& c) { return storage::FindQueuedAnalysis(c, keyframe_id); });
      lock.lock();
      looked_up = true;
      const auto again = outcomes_.find(keyframe_id);
      if (again != outcomes_.end() && again->second.state != AnalysisState::kPending) return again->second;
      // No row and no outcome: analysed earlier (before a restart, or long ago) or its keyframe was deleted.
      if (!row) return StatusOf(AnalysisState::kDone, keyframe_id);
      if (row->failed) {
        KeyframeAnalysisStatus s = StatusOf(AnalysisState::kFailed, keyframe_id);
        s.attempts = row->attempts;
        s.last_error = row->last_error;
        return s;
      }
      continue;
    }
    const std::uint64_t seen = generation_;
    if (!changed_.wait_until(lock, deadline, [&] { return generation_ != seen; })) {
      const auto retrying = outcomes_.find(keyframe_id);  // a failed attempt, retrying
      return retrying != outcomes_.end() ? retrying->second : StatusOf(AnalysisState::kPending, keyframe_id);
    }
  }
}

AnalysisQueueView AnalysisQueue::View(const std::optional<std::string>& map) {
  const storage::AnalysisQueueSummary s = store_.Read([&](storage::Connection& c) {
    if (map) RequireMap(c, *map);
    return storage::SummariseAnalysisQueue(c, map);
  });
  AnalysisQueueView v;
  v.pending = s.pending;
  v.failed = s.failed;
  v.retrying = s.retrying;
  v.failures = s.failures;
  if (s.oldest_enqueued_ns) v.oldest_pending_age_s = std::max<double>(0.0, static_cast<double>(clock_.NowNs() - *s.oldest_enqueued_ns) * 1e-9);
  std::lock_guard<std::mutex> lock(mutex_);
  v.running = map ? static_cast<std::int64_t>(running_maps_.count(*map)) : static_cast<std::int64_t>(running_maps_.size());
  return v;
}

AnalysisCounters AnalysisQueue::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  AnalysisCounters out = counters_;
  out.computed_in_write = events_.analyses_in_write();
  return out;
}

}  // namespace anchordb::services
