#include "api/job_service.h"

#include <chrono>

#include "schema/error.h"
#include "storage/forgetting.h"
#include "storage/repositories.h"

namespace anchordb::api {
namespace {

constexpr const char* kInterrupted = "interrupted by a server stop";

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void SetJobStatus(storage::Connection& c, std::int64_t id, const std::string& status, const std::string& stage,
                  double progress, const Json* result, const std::string* error) {
  storage::Statement s(c,
                       "UPDATE jobs SET status = ?, stage = ?, progress = ?, result = coalesce(?, result), "
                       "error = ?, updated_ns = ? WHERE id = ?");
  s.Bind(1, status).Bind(2, stage).Bind(3, progress);
  if (result) s.Bind(4, result->dump());
  else s.BindNull(4);
  if (error) s.Bind(5, *error);
  else s.BindNull(5);
  s.Bind(6, NowNs()).Bind(7, id).Run();
}

}  // namespace

JobService::JobService(storage::Store& store, JobSettings settings) : store_(store), settings_(std::move(settings)) {
  interrupted_at_start_ = store_.Write([](storage::Connection& c) {
    storage::Statement s(c,
                         "UPDATE jobs SET status = 'failed', error = ?1 || CASE WHEN stage <> '' THEN ' (stage ' || "
                         "stage || ')' ELSE '' END, updated_ns = ?2 WHERE status IN ('queued', 'running')");
    s.Bind(1, std::string(kInterrupted)).Bind(2, NowNs()).Run();
    return static_cast<int>(c.Changes());
  });
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
  std::int64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) throw Error(ErrorCode::kOverloaded, "the server is stopping; no job is accepted");
    if (pending_ >= settings_.max_queued) {
      throw Error(ErrorCode::kOverloaded, "the job queue is full (" + std::to_string(settings_.max_queued) +
                                              " jobs); retry when a job has finished");
    }
    id = store_.Write([&](storage::Connection& c) {
      if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
      storage::Statement s(c,
                           "INSERT INTO jobs (kind, map_id, status, stage, progress, request, created_ns, updated_ns) "
                           "VALUES ('forget', ?, 'queued', '', 0, ?, ?, ?)");
      const std::int64_t now = NowNs();
      s.Bind(1, map).Bind(2, stored.dump()).Bind(3, now).Bind(4, now).Run();
      return static_cast<std::int64_t>(sqlite3_last_insert_rowid(c.handle()));
    });
    ++pending_;
  }
  wake_.notify_all();
  return {{"job", id}, {"status", "queued"}, {"kind", "forget"}, {"map", map}, {"request", stored}};
}

Json JobService::Get(std::int64_t id) {
  Json j = store_.Read([&](storage::Connection& c) -> Json {
    storage::Statement s(c,
                         "SELECT id, kind, map_id, status, stage, progress, request, result, error, created_ns, "
                         "updated_ns FROM jobs WHERE id = ?");
    s.Bind(1, id);
    if (!s.Step()) throw Error(ErrorCode::kNotFound, "job " + std::to_string(id) + " does not exist", "job");
    return {{"id", s.Int(0)},
            {"kind", s.Text(1)},
            {"map", s.IsNull(2) ? Json(nullptr) : Json(s.Text(2))},
            {"status", s.Text(3)},
            {"stage", s.Text(4)},
            {"progress", s.Double(5)},
            {"request", Json::parse(s.Text(6), nullptr, false)},
            {"result", s.IsNull(7) ? Json(nullptr) : Json::parse(s.Text(7), nullptr, false)},
            {"error", s.IsNull(8) ? Json(nullptr) : Json(s.Text(8))},
            {"created_ns", s.Int(9)},
            {"updated_ns", s.Int(10)}};
  });
  std::lock_guard<std::mutex> lock(mutex_);
  if (live_id_ == id && j["status"] == "running") {
    j["stage"] = live_stage_;
    j["progress"] = live_progress_;
  }
  return j;
}

bool JobService::WaitIdle(double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  return idle_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return pending_ == 0; });
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
      id = store_.Read([](storage::Connection& c) -> std::int64_t {
        storage::Statement s(c, "SELECT id FROM jobs WHERE status = 'queued' ORDER BY id LIMIT 1");
        return s.Step() ? s.Int(0) : 0;
      });
    } catch (const std::exception&) {
      id = 0;
    }
    if (id == 0) {
      // The queued row vanished (its map was deleted, which cascades to its jobs): nothing to run for it.
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_ > 0) --pending_;
      if (pending_ == 0) idle_.notify_all();
      continue;
    }
    RunJob(id);
    std::lock_guard<std::mutex> lock(mutex_);
    if (pending_ > 0) --pending_;
    live_id_ = 0;
    if (pending_ == 0) idle_.notify_all();
  }
}

void JobService::RunJob(std::int64_t id) {
  std::string map;
  storage::ForgetRequest request;
  bool committed = false;
  Json result;
  try {
    const auto row = store_.Write([&](storage::Connection& c) {
      storage::Statement s(c, "SELECT map_id, request FROM jobs WHERE id = ?");
      s.Bind(1, id);
      if (!s.Step()) throw Error(ErrorCode::kNotFound, "job vanished");
      std::pair<std::string, std::string> out{s.Text(0), s.Text(1)};
      SetJobStatus(c, id, "running", "forgetting", 0.0, nullptr, nullptr);
      return out;
    });
    map = row.first;
    request = storage::ParseForgetRequest(Json::parse(row.second));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      live_id_ = id;
      live_stage_ = "forgetting";
      live_progress_ = 0.0;
    }
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
        storage::Statement s(c, "SELECT result IS NOT NULL FROM jobs WHERE id = ?");
        s.Bind(1, id);
        return s.Step() && s.Int(0) != 0;
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

}  // namespace anchordb::api
