#include "services/jobs/job_service.h"

#include "storage/job_repository.h"

#include <chrono>

#include "schema/error.h"
#include "storage/backup.h"
#include "storage/forgetting.h"
#include "storage/repositories.h"

namespace anchordb::services {
namespace {

constexpr const char* kInterrupted = "interrupted by a server stop";

// The stage a job of `kind` starts in.
const char* FirstStage(const std::string& kind) { return kind == "backup" ? "copying" : "forgetting"; }

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void SetJobStatus(storage::Connection& c, std::int64_t id, const std::string& status, const std::string& stage,
                  double progress, const Json* result, const std::string* error) {
  const std::string result_json = result ? result->dump() : std::string();
  storage::SetJobStatus(c, id, status, stage, progress, result ? &result_json : nullptr, error, NowNs());
}

}  // namespace

JobService::JobService(storage::Store& store, JobSettings settings) : store_(store), settings_(std::move(settings)) {
  interrupted_at_start_ = store_.Write(
      [](storage::Connection& c) { return storage::MarkUnfinishedJobsFailed(c, kInterrupted, NowNs()); });
  worker_ = std::thread([this] { Worker(); });
}

JobService::~JobService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    interrupt_ = true;
    if (live_connection_) sqlite3_interrupt(live_connection_->handle());
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

Json JobService::SubmitForget(const std::string& map, const Json& body) {
  const storage::ForgetRequest request = storage::ParseForgetRequest(body);  // throws on bad input: nothing queued
  Json stored = {{"policy", storage::ToJson(request.policy)}, {"dry_run", request.dry_run}};
  if (request.now_ns) stored["now"] = *request.now_ns;
  const std::int64_t id = Enqueue("forget", map, stored);
  return {{"job", id}, {"status", "queued"}, {"kind", "forget"}, {"map", map}, {"request", stored}};
}

Json JobService::SubmitBackup(const Json& body) {
  json::RejectUnknownKeys(body, {"label"});
  const std::string label = json::OptionalString(body, "label", 64).value_or("");
  if (!label.empty()) json::CheckId(label, "label");  // it becomes part of a file name
  if (settings_.backup_dir.empty()) throw Error(ErrorCode::kUnprocessable, "this server has no backup_dir", "backup_dir");
  const std::string file = storage::BackupFileName(settings_.backup_dir, store_.path(), NowNs(), label);
  const Json stored = {{"file", file}};
  const std::int64_t id = Enqueue("backup", std::nullopt, stored);
  return {{"job", id}, {"status", "queued"}, {"kind", "backup"}, {"map", nullptr}, {"request", stored}};
}

std::int64_t JobService::Enqueue(const std::string& kind, const std::optional<std::string>& map, const Json& request) {
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
      return storage::InsertJob(c, kind, map, request.dump(), NowNs());
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

Json JobService::Get(std::int64_t id) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::FindJob(c, id); });
  if (!r) throw Error(ErrorCode::kNotFound, "job " + std::to_string(id) + " does not exist", "job");
  Json j = {{"id", r->id},
            {"kind", r->kind},
            {"map", r->map_id ? Json(*r->map_id) : Json(nullptr)},
            {"status", r->status},
            {"stage", r->stage},
            {"progress", r->progress},
            {"request", Json::parse(r->request_json, nullptr, false)},
            {"result", r->result_json ? Json::parse(*r->result_json, nullptr, false) : Json(nullptr)},
            {"error", r->error ? Json(*r->error) : Json(nullptr)},
            {"created_ns", r->created_ns},
            {"updated_ns", r->updated_ns}};
  std::lock_guard<std::mutex> lock(mutex_);
  if (live_id_ == id && j["status"] == "running") {
    j["stage"] = live_stage_;
    j["progress"] = live_progress_;
  }
  return j;
}

bool JobService::WaitIdle(double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  return idle_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return pending_ == 0 && reserved_ == 0; });
}

void JobService::Worker() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_ > 0; });
      if (stop_) return;
    }
    std::int64_t id = 0;
    try {
      id = store_.Read([](storage::Connection& c) { return storage::NextQueuedJob(c).value_or(0); });
    } catch (const std::exception&) {
      id = 0;
    }
    if (id == 0) {
      // The queued row vanished (its map was deleted, which cascades to its jobs): nothing to run for it.
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_ > 0) --pending_;
      if (pending_ == 0 && reserved_ == 0) idle_.notify_all();
      continue;
    }
    RunJob(id);
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_ > 0) --pending_;
    live_id_ = 0;
    if (pending_ == 0 && reserved_ == 0) idle_.notify_all();
  }
}

void JobService::RunJob(std::int64_t id) {
  std::string map;
  storage::ForgetRequest request;
  bool committed = false;
  Json result;
  try {
    const auto job = store_.Write([&](storage::Connection& c) {
      auto r = storage::FindJob(c, id);
      if (!r) throw Error(ErrorCode::kNotFound, "job vanished");
      SetJobStatus(c, id, "running", FirstStage(r->kind), 0.0, nullptr, nullptr);
      return *r;
    });
    {
      std::lock_guard<std::mutex> lock(mutex_);
      live_id_ = id;
      live_stage_ = FirstStage(job.kind);
      live_progress_ = 0.0;
    }
    if (job.kind == "backup") {
      RunBackup(id, Json::parse(job.request_json).at("file").get<std::string>());
      return;
    }
    map = job.map_id.value_or("");
    request = storage::ParseForgetRequest(Json::parse(job.request_json));
    storage::ConnectionOptions options;
    options.busy_timeout_ms = settings_.busy_timeout_ms;
    options.synchronous = settings_.synchronous;
    storage::Connection connection(store_.path(), options);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      live_connection_ = &connection;
    }
    struct Unregister {
      JobService* self;
      ~Unregister() {
        std::lock_guard<std::mutex> lock(self->mutex_);
        self->live_connection_ = nullptr;
      }
    } unregister{this};
    const auto progress = [&](std::string_view stage, double fraction) {
      if (interrupt_) throw Error(ErrorCode::kOverloaded, kInterrupted);
      std::lock_guard<std::mutex> lock(mutex_);
      live_stage_ = std::string(stage);
      live_progress_ = fraction;
    };
    const auto before_commit = [&](storage::Connection& c, const storage::ForgetReport& report) {
      // Recorded with the deletions: a kill after this commit finds the job done (or, with a vacuum still to run,
      // 'running' in stage vacuum with the committed result, which start-up marks failed/interrupted).
      const Json r = report.ToJson();
      if (request.policy.vacuum) SetJobStatus(c, id, "running", "vacuum", 0.9, &r, nullptr);
      else SetJobStatus(c, id, "succeeded", "done", 1.0, &r, nullptr);
    };
    const storage::ForgetReport report =
        storage::Forget(connection, map, request.policy, request.now_ns.value_or(NowNs()), request.dry_run, progress,
                        before_commit);
    committed = report.committed;
    result = report.ToJson();
    if (request.dry_run || request.policy.vacuum) {
      store_.Write([&](storage::Connection& c) { SetJobStatus(c, id, "succeeded", "done", 1.0, &result, nullptr); });
    }
  } catch (const std::exception& e) {
    std::string message = e.what();
    if (interrupt_) message = kInterrupted;
    try {
      // The forgetting commit stores the result with the deletions; a result means they happened (a vacuum failed).
      committed = committed || store_.Read([&](storage::Connection& c) {
        const auto r = storage::FindJob(c, id);
        return r && r->result_json.has_value();
      });
    } catch (const std::exception&) {
    }
    if (committed) message += " (after the deletions were committed: see result)";
    try {
      store_.Write([&](storage::Connection& c) {
        std::string stage;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          stage = live_stage_;
        }
        SetJobStatus(c, id, "failed", stage, 1.0, nullptr, &message);
      });
    } catch (const std::exception&) {
      // The job row cannot be updated (the database is gone or read-only): start-up marks it interrupted.
    }
  }
}

void JobService::RunBackup(std::int64_t id, const std::string& file) {
  const storage::BackupReport report =
      storage::Backup(store_.path(), file, settings_.busy_timeout_ms, [&](double fraction) {
        if (interrupt_) throw Error(ErrorCode::kOverloaded, kInterrupted);
        std::lock_guard<std::mutex> lock(mutex_);
        live_progress_ = 0.95 * fraction;  // the integrity check and the sync come after the copy
      });
  const Json result = report.ToJson();
  store_.Write([&](storage::Connection& c) { SetJobStatus(c, id, "succeeded", "done", 1.0, &result, nullptr); });
}

}  // namespace anchordb::services
