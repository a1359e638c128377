// The live change stream GET /v1/maps/{map}/events:stream over real HTTP on loopback: a subscriber follows a rendered
// lost-key scenario and a burst of dialog labels (over 1000 events), is cut off on purpose and by the server's
// response length, resumes with Last-Event-ID, and receives every stored event exactly once and in id order; job
// progress arrives on the same stream; the stream slots are bounded (503) and other clients are still served.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "sim/lost_key_scenario.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <atomic>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

namespace anchordb {
namespace event_stream_http_test {

using nlohmann::json;

struct SseMessage {
  std::string id, event, data;
};

// Incremental text/event-stream parser (the subset the server writes: id, event, data, retry, comments).
class SseParser {
 public:
  template <typename OnMessage>
  void Feed(const char* data, std::size_t size, OnMessage&& on_message) {
    buffer_.append(data, size);
    for (std::size_t end; (end = buffer_.find("\n\n")) != std::string::npos;) {
      const std::string block = buffer_.substr(0, end);
      buffer_.erase(0, end + 2);
      SseMessage m;
      bool any = false;
      std::size_t pos = 0;
      while (pos <= block.size()) {
        std::size_t nl = block.find('\n', pos);
        if (nl == std::string::npos) nl = block.size();
        const std::string line = block.substr(pos, nl - pos);
        pos = nl + 1;
        if (line.empty() || line[0] == ':') continue;
        const std::size_t colon = line.find(':');
        const std::string field = line.substr(0, colon);
        std::string value = colon == std::string::npos ? "" : line.substr(colon + 1);
        if (!value.empty() && value[0] == ' ') value.erase(0, 1);
        if (field == "id") m.id = value, any = true;
        if (field == "event") m.event = value, any = true;
        if (field == "data") m.data += value, any = true;
      }
      if (any && !m.data.empty()) on_message(m);
    }
  }
  void Reset() { buffer_.clear(); }

 private:
  std::string buffer_;
};

class EventStreamHttpTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> args) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("stream.sqlite"), std::move(args));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  json Ok(const std::string& method, const std::string& path, const std::string& body = "{}", int status = 200) {
    httplib::Result r = method == "GET" ? client_->Get(path) : client_->Post(path, body, "application/json");
    EXPECT_TRUE(r) << method << " " << path;
    if (!r) return json();
    EXPECT_EQ(r->status, status) << method << " " << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(EventStreamHttpTest, ThousandEventsArriveOnceAndInOrderAcrossForcedReconnects) {
  // Short responses (the server ends each after 2 s): natural reconnects on top of the forced ones.
  Start({"--synchronous=NORMAL", "--stream_max_duration_s=2", "--stream_poll_s=0.05"});
  Ok("POST", "/v1/maps", R"({"id":"home","name":"home"})", 201);

  std::mutex mutex;
  std::vector<SseMessage> received;  // change and label messages
  std::vector<json> job_messages;
  std::atomic<std::int64_t> stop_after{-1};  // set when the writer is done: the last event id to wait for
  std::atomic<bool> failed{false};
  std::atomic<bool> subscribed{false};
  std::atomic<bool> job_ended{false};  // a job message with a final status has arrived
  int connections = 0, forced = 0;
  std::string subscriber_error;
  // Joined on every way out of the test (a failed ASSERT returns early): the subscriber stops at its next message.
  struct Joiner {
    std::thread t;
    std::atomic<bool>& stop;
    ~Joiner() {
      stop = true;
      if (t.joinable()) t.join();
    }
  };
  Joiner subscriber{std::thread([&] {
    httplib::Client sse("127.0.0.1", server_->port());
    sse.set_read_timeout(30, 0);
    std::string last_id;
    std::int64_t since_cut = 0;
    int after_target = 0;
    while (!failed) {
      SseParser parser;
      httplib::Headers headers;
      if (!last_id.empty()) headers.emplace("Last-Event-ID", last_id);
      ++connections;
      bool cut = false;
      // Until a first message came, a reconnection must not start "after the newest event" (the default): a first
      // connection that ended before any event (max_duration_s on a slow run) would lose the events written between.
      auto r = sse.Get(last_id.empty() ? "/v1/maps/home/events:stream?after=0" : "/v1/maps/home/events:stream", headers,
          [&](const httplib::Response& response) {
            if (response.status != 200) failed = true, subscriber_error = "status " + std::to_string(response.status);
            subscribed = true;
            return response.status == 200;
          },
          [&](const char* data, std::size_t size) {
            parser.Feed(data, size, [&](const SseMessage& m) {
              if (m.event == "job") {
                std::lock_guard<std::mutex> lock(mutex);
                job_messages.push_back(json::parse(m.data));
                const json& status = job_messages.back()["status"];
                if (status == "succeeded" || status == "failed" || status == "cancelled") job_ended = true;
              } else {
                std::lock_guard<std::mutex> lock(mutex);
                received.push_back(m);
              }
              last_id = m.id;
              if (m.event != "job" && ++since_cut == 300) cut = true;  // every 300 events: hang up mid-stream
            });
            return !cut && !failed;
          });
      if (cut) ++forced, since_cut = 0;
      // Done when the last stored event has arrived and the job's final document too (it may come after the last
      // event); a job that never reports its end is given 30 more connections (each ends within 2 s), then the
      // assertions below say what is missing.
      const std::int64_t target = stop_after.load();
      if (target >= 0 && !last_id.empty() && std::stoll(last_id) >= target) {
        if (job_ended || ++after_target > 30) return;
      }
      if (!r && !cut && r.error() != httplib::Error::Canceled && r.error() != httplib::Error::Read) {
        failed = true, subscriber_error = httplib::to_string(r.error());
      }
    }
  }), failed};
  for (int i = 0; i < 200 && !subscribed; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(subscribed.load()) << subscriber_error;

  // A scenario: rendered visits with real change events, the lost-key move and dialog labels.
  sim::LostKeyOptions o;
  o.kind_sensor = true;
  o.seed = 10;
  o.create_map = false;
  const sim::LostKeyResult scenario = sim::RunLostKeyScenario(*client_, o);
  ASSERT_FALSE(scenario.events.empty());
  // A job of the map while the stream is open (a forgetting dry run): its progress comes on the stream.
  const json ticket = Ok("POST", "/v1/maps/home:forget", R"({"policy":{"event_max_age_s":1e9},"dry_run":true})", 202);
  // Then dialog labels until the map holds more than 1000 events.
  const json instances = Ok("GET", "/v1/maps/home/instances?kind=object")["instances"];
  ASSERT_FALSE(instances.empty());
  const char* words[] = {"keys", "cup", "phone", "wallet", "remote"};
  for (int i = 0; i < 1000; ++i) {
    const json& inst = instances[i % instances.size()];
    Ok("POST", "/v1/maps/home/instances/" + std::to_string(inst["id"].get<std::int64_t>()) + ":label",
       json({{"label", words[i % 5]}, {"source", "operator"}}).dump());
  }
  // Every stored event, through the paginated list.
  std::vector<json> stored;
  for (std::int64_t after = 0;;) {
    const json page = Ok("GET", "/v1/maps/home/events?limit=1000&after=" + std::to_string(after));
    for (const json& e : page["events"]) stored.push_back(e);
    if (!page.contains("next_after")) break;
    after = page["next_after"].get<std::int64_t>();
  }
  ASSERT_GE(stored.size(), 1000u);
  stop_after = stored.back()["id"].get<std::int64_t>();
  subscriber.t.join();
  ASSERT_FALSE(failed.load()) << subscriber_error;

  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(received.size(), stored.size()) << "connections " << connections << ", forced " << forced;
  for (std::size_t i = 0; i < stored.size(); ++i) {
    const json data = json::parse(received[i].data);
    ASSERT_EQ(std::stoll(received[i].id), stored[i]["id"].get<std::int64_t>()) << "message " << i;
    ASSERT_EQ(data, stored[i]) << "message " << i;
    EXPECT_EQ(received[i].event, stored[i]["type"] == "labelled" ? "label" : "change");
  }
  std::cout << "stream: " << received.size() << " events over " << connections << " connections (" << forced
            << " cut by the client), " << job_messages.size() << " job messages\n";
  EXPECT_GE(forced, 3);
  EXPECT_GT(connections, forced + 1);  // the server's own response ends too
  // The job: seen finished on the stream, and the same document GET /v1/jobs/{id} serves.
  const json final_job = Ok("GET", "/v1/jobs/" + std::to_string(ticket["job"].get<std::int64_t>()));
  bool seen_final = false;
  for (const json& j : job_messages) seen_final = seen_final || (j["id"] == final_job["id"] && j == final_job);
  EXPECT_TRUE(seen_final) << final_job.dump();
  EXPECT_EQ(final_job["status"], "succeeded");
  // And the job list of the map names it.
  const json jobs = Ok("GET", "/v1/jobs?map=home");
  ASSERT_FALSE(jobs["jobs"].empty());
  EXPECT_EQ(jobs["jobs"][0]["id"], ticket["job"]);
}

// A job that ends while the client is between two responses: the resumed stream sends its final state first (a
// fresh subscriber, which asked for nothing of the past, is not sent ended jobs).
TEST_F(EventStreamHttpTest, AJobThatEndedWhileTheClientWasAwayIsSentOnResume) {
  Start({"--stream_max_duration_s=1", "--stream_poll_s=0.05"});
  Ok("POST", "/v1/maps", R"({"id":"home","name":"home"})", 201);
  const json ticket = Ok("POST", "/v1/maps/home:forget", R"({"policy":{"event_max_age_s":1e9},"dry_run":true})", 202);
  const std::string job_path = "/v1/jobs/" + std::to_string(ticket["job"].get<std::int64_t>());
  json job = Ok("GET", job_path);
  for (int i = 0; i < 600 && (job["status"] == "queued" || job["status"] == "running"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    job = Ok("GET", job_path);
  }
  ASSERT_EQ(job["status"], "succeeded") << job.dump();
  // Each response ends after 1 s: collect the job messages of one whole response.
  const auto job_messages = [&](const httplib::Headers& headers, const std::string& path) {
    httplib::Client sse("127.0.0.1", server_->port());
    sse.set_read_timeout(10, 0);
    SseParser parser;
    std::vector<json> jobs;
    sse.Get(path, headers, [](const httplib::Response& r) { return r.status == 200; },
            [&](const char* data, std::size_t size) {
              parser.Feed(data, size, [&](const SseMessage& m) {
                if (m.event == "job") jobs.push_back(json::parse(m.data));
              });
              return true;
            });
    return jobs;
  };
  const auto resumed = job_messages({{"Last-Event-ID", "0"}}, "/v1/maps/home/events:stream");
  ASSERT_EQ(resumed.size(), 1u);
  EXPECT_EQ(resumed[0], job);
  EXPECT_EQ(job_messages({}, "/v1/maps/home/events:stream?after=0").size(), 1u);
  EXPECT_TRUE(job_messages({}, "/v1/maps/home/events:stream").empty());
}

TEST_F(EventStreamHttpTest, StreamSlotsAreBoundedOthersAreServedAndBadRequestsRefused) {
  Start({"--stream_max_streams=2", "--stream_max_duration_s=30"});
  Ok("POST", "/v1/maps", R"({"id":"home","name":"home"})", 201);
  // Unknown map and a bad Last-Event-ID: JSON errors before any stream starts.
  auto unknown = client_->Get("/v1/maps/nowhere/events:stream");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(json::parse(unknown->body)["error"]["code"], "not_found");
  auto bad = client_->Get("/v1/maps/home/events:stream", {{"Last-Event-ID", "x12"}});
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(json::parse(bad->body)["error"]["field"], "Last-Event-ID");

  // Two streams open (each waits for its first bytes), then a third is refused at once.
  std::atomic<int> open{0};
  std::atomic<bool> release{false};
  struct Streams {
    std::vector<std::thread> threads;
    std::atomic<bool>& release;
    ~Streams() {
      release = true;
      for (auto& t : threads) if (t.joinable()) t.join();
    }
  } streams{{}, release};
  for (int i = 0; i < 2; ++i) {
    streams.threads.emplace_back([&] {
      httplib::Client sse("127.0.0.1", server_->port());
      sse.Get("/v1/maps/home/events:stream", httplib::Headers{},
              [&](const httplib::Response& r) { return r.status == 200; },
              [&](const char*, std::size_t) {
                static thread_local bool counted = false;
                if (!counted) counted = true, ++open;
                return !release.load();
              });
    });
  }
  for (int i = 0; i < 500 && open < 2; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(open.load(), 2);
  auto refused = client_->Get("/v1/maps/home/events:stream");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 503);
  EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
  EXPECT_EQ(json::parse(refused->body)["error"]["code"], "overloaded");
  // Everyone else is served meanwhile.
  for (int i = 0; i < 20; ++i) Ok("GET", "/v1/maps/home/events");
  // A label while the streams are open reaches them; then they hang up and the slots are free again.
  Ok("POST", "/v1/maps/home/instances", R"({"kind":"object","label":"cup","position":[1,0,0]})", 201);
  release = true;
  for (auto& t : streams.threads) t.join();
  bool admitted = false;
  for (int i = 0; i < 100 && !admitted; ++i) {
    httplib::Client sse("127.0.0.1", server_->port());
    int status = 0;
    sse.Get("/v1/maps/home/events:stream", httplib::Headers{},
            [&](const httplib::Response& r) { status = r.status; return false; }, [](const char*, std::size_t) { return false; });
    admitted = status == 200;
    if (!admitted) std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the server sees the hang-up at its next poll
  }
  EXPECT_TRUE(admitted);
}

}  // namespace
}  // namespace anchordb
