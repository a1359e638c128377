// The live change stream (api/stream_routes.h): one response polls the store for events after its cursor and for
// the map's job states, and writes each as a Server-Sent Event.
#include "api/stream_routes.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <thread>

#include "api/event_json.h"
#include "api/job_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kEventsPerPoll = 500;  // a longer backlog is sent over consecutive polls without waiting
constexpr int kJobsWatched = 50;     // the map's newest jobs are watched

// Where a (re)connecting client resumes: Last-Event-ID, else ?after=, else after the newest event.
std::int64_t StartCursor(const httplib::Request& req, std::int64_t newest) {
  if (req.has_header("Last-Event-ID")) {
    const std::string text = req.get_header_value("Last-Event-ID");
    if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
      throw Error(ErrorCode::kInvalidArgument, "Last-Event-ID must be an event id (a non-negative integer)", "Last-Event-ID");
    }
    return std::stoll(text);
  }
  return QueryInteger(req, "after", newest, 0, INT64_MAX);
}

std::string JobKey(const JobView& j) {
  return std::string(JobStatusId(j.status)) + "|" + j.stage + "|" + std::to_string(std::lround(j.progress * 100.0));
}

struct Stream {
  Stream(std::shared_ptr<std::atomic<int>> open_streams, std::string map_id, std::int64_t from, bool resuming)
      : open(std::move(open_streams)), map(std::move(map_id)), cursor(from), resumed(resuming) {}
  ~Stream() { --*open; }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  std::shared_ptr<std::atomic<int>> open;
  std::string map;
  std::int64_t cursor;  // the last event id sent
  bool resumed;         // Last-Event-ID or after= given: the client may have missed a job's end while away
  bool started = false;
  Clock::time_point deadline{}, last_write{};
  std::map<std::int64_t, std::string> jobs_sent;  // job id -> JobKey last sent (or seen finished at the start)
};

std::string Message(std::int64_t id, const char* kind, const Json& data) {
  return "id: " + std::to_string(id) + "\nevent: " + kind + "\ndata: " +
         data.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n\n";
}

// One call of the chunked provider: what happened since the last call, then a wait of poll_s (unless more is due).
bool Poll(Stream& s, EventService& events, JobService& jobs, httplib::DataSink& sink) {
  const EventSettings::Stream& o = events.settings().stream;
  std::string out;
  const auto now = Clock::now();
  if (!s.started) {
    s.started = true;
    s.deadline = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.max_duration_s));
    out = "retry: " + std::to_string(o.retry_ms) + "\n: events of map " + s.map + " after " + std::to_string(s.cursor) + "\n\n";
    const auto recent_ns = jobs.NowNs() - static_cast<std::int64_t>(o.resume_jobs_s * 1e9);
    for (const JobView& j : jobs.List(s.map, 0, kJobsWatched)) {
      const bool active = j.status == JobStatus::kQueued || j.status == JobStatus::kRunning;
      if (active || (s.resumed && j.updated_ns >= recent_ns)) out += Message(s.cursor, "job", ToJson(j));
      s.jobs_sent[j.id] = JobKey(j);
    }
  } else if (now >= s.deadline) {
    sink.done();  // the client reconnects after `retry` with Last-Event-ID
    return true;
  }
  EventQuery q;
  q.after_id = s.cursor;
  q.limit = kEventsPerPoll;
  const EventPage page = events.ListEvents(s.map, q);
  for (const EventView& e : page.events) {
    out += Message(e.id, e.type == "labelled" ? "label" : "change", EventJson(e));
    s.cursor = e.id;
  }
  if (s.jobs_sent.size() > 4 * kJobsWatched) s.jobs_sent.clear();  // bounded; old ids are not listed again anyway
  for (const JobView& j : jobs.List(s.map, 0, kJobsWatched)) {
    std::string key = JobKey(j);
    auto& sent = s.jobs_sent[j.id];
    if (sent != key) out += Message(s.cursor, "job", ToJson(j));
    sent = std::move(key);
  }
  if (out.empty() && now - s.last_write >= std::chrono::duration<double>(o.heartbeat_s)) out = ": keep-alive\n\n";
  if (!out.empty()) {
    if (!sink.write(out.data(), out.size())) return false;
    s.last_write = now;
  }
  if (!sink.is_writable()) return false;  // sends what was written; false once the client hung up
  if (static_cast<int>(page.events.size()) < kEventsPerPoll) {
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_s));
  }
  return true;
}

}  // namespace

void RegisterStreamRoutes(Router& router, EventService& events, JobService& jobs) {
  auto open = std::make_shared<std::atomic<int>>(0);
  router.Add("GET", "/v1/maps/{map}/events:stream", Role::kReader,
      "Server-Sent Events of the map's change events, labels and job progress as they happen; resumable with "
      "Last-Event-ID (or after=)",
      [&events, &jobs, open](const httplib::Request& req, const PathParams& p) {
        const std::string map = p["map"];
        const std::int64_t cursor = StartCursor(req, events.LatestEventId(map));  // unknown map: 404 here
        const int max_streams = events.settings().stream.max_streams;
        if (++*open > max_streams) {
          --*open;
          throw Error(ErrorCode::kOverloaded, "every live stream slot is taken (" + std::to_string(max_streams) +
                                                  " open); retry after 1 s");
        }
        auto stream = std::make_shared<Stream>(open, map, cursor, req.has_header("Last-Event-ID") || req.has_param("after"));
        Response r;
        r.content_type = "text/event-stream";
        r.headers["Cache-Control"] = "no-cache";
        r.headers["X-Accel-Buffering"] = "no";
        r.stream = [stream, &events, &jobs](httplib::DataSink& sink) { return Poll(*stream, events, jobs, sink); };
        return r;
      });
}

}  // namespace anchordb::api
