#include "services/jobs/job_service.h"

#include <unistd.h>

#include <chrono>
#include <cstdint>

#include "schema/error.h"
#include "services/jobs/backup_job.h"
#include "services/jobs/forget_job.h"
#include "services/common/require.h"
#include "storage/job_repository.h"
#include "storage/repositories.h"

namespace anchordb::services {
namespace {

constexpr const char* kInterrupted = "interrupted by a server stop";
constexpr const char* kCancelled = "cancelled";

Error NoJob(std::int64_t id) { return Error(ErrorCode::kNotFound, "job " + std::to_string(id) + " does not exist", "job"); }

}  // namespace

// The running job as its runner sees it.
class JobService::Context final : public JobContext {
 public:
  Context(JobService& service, storage::JobRecord record) : service_(service), record_(std::move(record)) {}
  std::int64_t id() const override { return record_.id; }
  const std::optional<std::string>& map() const override { return record_.map_id; }
  const std::string& request() const override { return record_.request.encoded; }
  std::int64_t NowNs() const override { return service_.clock_.NowNs(); }
  void Progress(std::string_view stage, double fraction) override {
    ThrowIfCancelled();
    std::lock_guard<std::mutex> lock(service_.mutex_);
    service_.live_stage_ = std::string(stage);
    service_.live_progress_ = fraction;
  }
  void Progress(double fraction) override {
    ThrowIfCancelled();
    std::lock_guard<std::mutex> lock(service_.mutex_);
    service_.live_progress_ = fraction;
  }
  bool Cancelled() const override { return service_.interrupt_ || service_.cancel_; }
  void SetInterruptible(storage::Connection* c) override {
    std::lock_guard<std::mutex> lock(service_.mutex_);
    service_.live_connection_ = c;
    if (c && Cancelled()) c->Interrupt();
  }
  void Record(storage::Connection& c, JobStatus status, const std::string& stage, double progress,
              const std::string* result_document) override {
    service_.SetStatus(c, record_.id, status, stage, progress, result_document, nullptr);
  }

 private:
  void ThrowIfCancelled() const {
    if (service_.interrupt_) throw Error(ErrorCode::kOverloaded, kInterrupted);
    if (service_.cancel_) throw Error(ErrorCode::kOverloaded, kCancelled);
  }
  JobService& service_;
  storage::JobRecord record_;
};

JobService::JobService(storage::Store& store, JobSettings settings, const Clock& clock)
    : store_(store), settings_(std::move(settings)), clock_(clock) {
  // A job stopped after its work committed says so. Only the kinds registered here can: the others (Register)
  // come after this start-up pass, and none of them records a result before its end today.
  std::map<std::string, std::string> notes_after_result;
  for (JobKind kind : {ForgetJobKind(store_.path(), settings_), BackupJobKind(store_.path(), settings_)}) {
    if (!kind.note_when_failed_after_result.empty()) notes_after_result[kind.name] = kind.note_when_failed_after_result;
    registry_.Register(std::move(kind));
  }
  notes_after_result_ = std::move(notes_after_result);
  storage::ConnectionOptions options;
  options.busy_timeout_ms = settings_.busy_timeout_ms;
  const auto seed = static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
                    (static_cast<std::uint64_t>(::getpid()) << 40) ^ reinterpret_cast<std::uintptr_t>(this);
  presence_ = std::make_unique<storage::ServerPresence>(store_.path(), options, seed);
  interrupted_at_start_ = MarkJobsOfGoneServers(true);
  worker_ = std::thread([this] { Worker(); });
}

JobService::~JobService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    interrupt_ = true;
    if (live_connection_) live_connection_->Interrupt();
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

int JobService::MarkJobsOfGoneServers(bool at_once) {
  const auto servers = store_.Read([](storage::Connection& c) { return storage::UnfinishedJobServers(c); });
  std::set<std::optional<std::string>> gone;
  for (const auto& id : servers) {
    if (!id || !presence_->Running(*id)) gone.insert(id);
  }
  std::set<std::optional<std::string>> mark;
  for (const auto& id : gone) {
    if (at_once || gone_at_last_pass_.count(id)) mark.insert(id);
  }
  gone_at_last_pass_ = std::move(gone);
  if (mark.empty()) return 0;
  return store_.Write([&](storage::Connection& c) {
    int n = 0;
    for (const auto& id : mark) n += storage::MarkUnfinishedJobsFailed(c, id, kInterrupted, clock_.NowNs(), notes_after_result_);
    return n;
  });
}

void JobService::Reap() {
  try {
    presence_->Hold();  // after a failover: this server's lock again, before it judges others
    interrupted_since_start_ += MarkJobsOfGoneServers(false);
  } catch (const std::exception&) {
    // The database cannot answer now (a failover, a full disk): the next pass looks again.
  }
}

void JobService::Register(JobKind kind) {
  std::lock_guard<std::mutex> lock(mutex_);
  registry_.Register(std::move(kind));
}

void JobService::SetStatus(storage::Connection& c, std::int64_t id, JobStatus status, const std::string& stage,
                           double progress, const std::string* result_document, const std::string* error) const {
  storage::SetJobStatus(c, id, status, stage, progress, result_document, error, clock_.NowNs());
}

JobTicket JobService::Submit(const std::string& kind, const std::optional<std::string>& map,
                             const std::string& request_document) {
  std::shared_ptr<const JobKind> k;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    k = registry_.Find(kind);
  }
  if (!k) throw Error(ErrorCode::kInvalidArgument, "unknown job kind '" + kind + "'", "kind");
  if (k->needs_map != map.has_value()) {
    throw Error(ErrorCode::kInvalidArgument, "a " + kind + " job is " + (k->needs_map ? "" : "not ") + "for one map", "map");
  }
  if (k->check) k->check({map, request_document, clock_.NowNs()});  // throws on bad input: nothing queued
  return {Enqueue(kind, map, request_document), kind, map, JobDocument{request_document, {}}};
}

std::int64_t JobService::Enqueue(const std::string& kind, const std::optional<std::string>& map,
                             const std::string& request_document) {
  {
    // The queue slot is taken under the mutex, the job row written without it: the running job takes the mutex
    // (progress) while it holds the database's write lock, so waiting for that lock here under the mutex would
    // deadlock both until the busy timeout.
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) throw Error(ErrorCode::kOverloaded, "the server is stopping; no job is accepted");
    if (pending_ + reserved_ >= settings_.max_queued) {
      throw Error(ErrorCode::kOverloaded, "the job queue is full (" + std::to_string(settings_.max_queued) +
                                              " jobs); retry when a job has finished");
    }
    ++reserved_;
  }
  std::int64_t id = 0;
  try {
    id = store_.Write([&](storage::Connection& c) {
      if (map && !storage::FindMap(c, *map)) throw Error(ErrorCode::kNotFound, "map '" + *map + "' does not exist", "map");
      return storage::InsertJob(c, kind, map, request_document, clock_.NowNs(), presence_->id());
    });
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    --reserved_;
    if (pending_ == 0 && reserved_ == 0) idle_.notify_all();
    throw;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    --reserved_;
    ++pending_;  // the worker looks for a queued row only now that it is committed
  }
  wake_.notify_all();
  return id;
}

JobView JobService::Get(std::int64_t id) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::FindJob(c, id); });
  if (!r) throw NoJob(id);
  std::lock_guard<std::mutex> lock(mutex_);
  return ViewOf(*r);
}

std::vector<JobView> JobService::List(const std::optional<std::string>& map, std::int64_t before_id, int limit) {
  if (limit < 1 || limit > 1000) throw Error(ErrorCode::kInvalidArgument, "limit must be in [1, 1000]", "limit");
  const auto records = store_.Read([&](storage::Connection& c) {
    if (map) RequireMap(c, *map);
    return storage::ListJobs(c, map, before_id, limit);
  });
  std::vector<JobView> out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& r : records) out.push_back(ViewOf(r));
  return out;
}

JobView JobService::ViewOf(const storage::JobRecord& r) const {
  JobView v{r.id, r.kind, r.map_id, r.status, r.stage, r.progress, r.request, r.result,
            r.error, r.created_ns, r.updated_ns};
  if (const auto f = unrecorded_failures_.find(r.id); f != unrecorded_failures_.end() && v.status != JobStatus::kSucceeded) {
    v.status = JobStatus::kFailed;
    v.error = f->second;
    return v;
  }
  if (live_id_ == r.id && v.status == JobStatus::kRunning) {
    v.stage = live_stage_;
    v.progress = live_progress_;
  }
  return v;
}

bool JobService::Cancel(std::int64_t id) {
  const std::string cancelled = kCancelled;
  const JobStatus was = store_.Write([&](storage::Connection& c) {
    const auto r = storage::FindJob(c, id);
    if (!r) throw NoJob(id);
    const JobStatus status = r->status;
    if (status == JobStatus::kQueued) SetStatus(c, id, JobStatus::kFailed, r->stage, r->progress, nullptr, &cancelled);
    return status;
  });
  if (was == JobStatus::kQueued) return true;  // the worker skips it
  if (was != JobStatus::kRunning) return false;
  // Running: the worker set live_id_ in the transaction that marked it running, so it is this job unless it ended.
  std::lock_guard<std::mutex> lock(mutex_);
  if (live_id_ != id) return false;
  cancel_ = true;
  if (live_connection_) live_connection_->Interrupt();
  return true;
}

bool JobService::WaitIdle(double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  return idle_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return pending_ == 0 && reserved_ == 0; });
}

void JobService::Worker() {
  const auto interval = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(settings_.reap_interval_s));
  auto next_reap = std::chrono::steady_clock::now() + interval;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_until(lock, next_reap, [&] { return stop_ || pending_ > 0; });
      if (stop_) return;
    }
    if (std::chrono::steady_clock::now() >= next_reap) {  // also between jobs of a busy queue
      Reap();
      next_reap = std::chrono::steady_clock::now() + interval;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_ == 0) continue;
    }
    RecordFailures();
    std::map<std::int64_t, std::string> failed;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      failed = unrecorded_failures_;
    }
    std::int64_t id = 0;
    try {
      id = store_.Read([&](storage::Connection& c) {
        auto next = storage::NextQueuedJob(c, presence_->id());
        while (next && failed.count(*next)) next = storage::NextQueuedJob(c, presence_->id(), *next);  // failed, not yet recorded
        return next.value_or(0);
      });
    } catch (const std::exception&) {
      // The queue could not be read now (an I/O error, memory ran out): the job is still queued, so it is not given
      // up (that would leave it queued for good); the worker looks again shortly.
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(100), [&] { return stop_; });
      continue;
    }
    if (id == 0) {
      // The queued row vanished (its map was deleted, which cascades to its jobs, or it was cancelled).
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_ > 0) --pending_;
      if (pending_ == 0 && reserved_ == 0) idle_.notify_all();
      continue;
    }
    RunJob(id);
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_ > 0) --pending_;
    live_id_ = 0;
    cancel_ = false;
    if (pending_ == 0 && reserved_ == 0) idle_.notify_all();
  }
}

void JobService::RunJob(std::int64_t id) {
  std::shared_ptr<const JobKind> kind;
  try {
    const auto job = store_.Write([&](storage::Connection& c) -> std::optional<storage::JobRecord> {
      auto r = storage::FindJob(c, id);
      if (!r) throw Error(ErrorCode::kNotFound, "job vanished");
      if (r->status != JobStatus::kQueued) return std::nullopt;  // cancelled after the worker picked it
      std::lock_guard<std::mutex> lock(mutex_);
      kind = registry_.Find(r->kind);
      live_id_ = id;
      live_stage_ = kind ? kind->first_stage : "";
      live_progress_ = 0.0;
      cancel_ = false;
      if (!kind) throw Error(ErrorCode::kInternal, "no runner for job kind '" + r->kind + "'");
      SetStatus(c, id, JobStatus::kRunning, kind->first_stage, 0.0, nullptr, nullptr);
      return r;
    });
    if (!job) return;
    Context context(*this, *job);
    const std::optional<std::string> result = kind->run(context);
    if (result) store_.Write([&](storage::Connection& c) { SetStatus(c, id, JobStatus::kSucceeded, "done", 1.0, &*result, nullptr); });
  } catch (const std::exception& e) {
    Fail(id, kind.get(), e.what());
  }
}

void JobService::Fail(std::int64_t id, const JobKind* kind, const std::string& what) {
  std::string message = interrupt_ ? kInterrupted : cancel_ ? kCancelled : what;
  try {
    // A runner records its result with the work it describes; a result means that work was committed.
    const bool has_result = store_.Read([&](storage::Connection& c) {
      const auto r = storage::FindJob(c, id);
      return r && r->result.has_value();
    });
    if (has_result && kind) message += kind->note_when_failed_after_result;
  } catch (const std::exception&) {
  }
  try {
    store_.Write([&](storage::Connection& c) {
      std::string stage;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        stage = live_stage_;
      }
      SetStatus(c, id, JobStatus::kFailed, stage, 1.0, nullptr, &message);
    });
  } catch (const std::exception&) {
    // The job row cannot be updated now (the disk fails or is full): served as failed and written later; if the
    // server stops first, start-up marks it interrupted.
    std::lock_guard<std::mutex> lock(mutex_);
    unrecorded_failures_[id] = message;
  }
}

void JobService::RecordFailures() {
  std::map<std::int64_t, std::string> failed;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    failed = unrecorded_failures_;
  }
  for (const auto& failure : failed) {
    const std::int64_t id = failure.first;  // named copies: clang 14 cannot capture a structured binding
    const std::string& message = failure.second;
    try {
      store_.Write([&](storage::Connection& c) {
        const auto r = storage::FindJob(c, id);
        if (r && (r->status == JobStatus::kQueued || r->status == JobStatus::kRunning)) {
          SetStatus(c, id, JobStatus::kFailed, r->stage, 1.0, nullptr, &message);
        }
      });
    } catch (const std::exception&) {
      continue;  // still refused: kept for the next wake
    }
    std::lock_guard<std::mutex> lock(mutex_);
    unrecorded_failures_.erase(id);
  }
}

}  // namespace anchordb::services
