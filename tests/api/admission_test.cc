// Admission control of every write route in one place (api/http_api.cc): with `max_pending_writes` writes in
// flight, one more write is refused at once with 503 + Retry-After and counted in /metrics, while reads go on; the
// slot is given back when a write finishes. Real cpp-httplib server on loopback; the write in flight is held by a
// latch, so nothing depends on timing.
#include "api/http_api.h"

#include <gtest/gtest.h>

#include <condition_variable>
#include <mutex>
#include <thread>

namespace anchordb::api {
namespace admission_test {

class Latch {
 public:
  void Arrive() {
    std::lock_guard<std::mutex> lock(mutex_);
    arrived_ = true;
    changed_.notify_all();
  }
  void WaitArrived() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return arrived_; });
  }
  void Release() {
    std::lock_guard<std::mutex> lock(mutex_);
    released_ = true;
    changed_.notify_all();
  }
  void WaitReleased() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return released_; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool arrived_ = false;
  bool released_ = false;
};

TEST(AdmissionTest, AWriteBeyondTheLimitIsRefusedAtOnceWithRetryAfterAndCounted) {
  HttpOptions options;
  options.max_pending_writes = 1;
  HttpApi api(options);
  Latch held;
  int writes_done = 0;
  api.router().Add("POST", "/v1/test/slow", Role::kWriter, "a write held by the test", [&](const auto&, const auto&) {
    held.Arrive();
    held.WaitReleased();
    ++writes_done;
    return Response{200, "application/json", "{}", {}};
  });
  api.router().Add("PUT", "/v1/test/fast", Role::kWriter, "a write", [&](const auto&, const auto&) {
    ++writes_done;
    return Response{200, "application/json", "{}", {}};
  });
  api.router().Add("GET", "/v1/test/read", Role::kReader, "a read", [](const auto&, const auto&) {
    return Response{200, "application/json", "{\"read\":true}", {}};
  });
  httplib::Server server;
  api.Mount(server);
  const int port = server.bind_to_any_port("127.0.0.1");
  ASSERT_GT(port, 0);
  std::thread serving([&] { server.listen_after_bind(); });

  std::thread slow([&] {
    httplib::Client c("127.0.0.1", port);
    const auto r = c.Post("/v1/test/slow", "{}", "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  });
  held.WaitArrived();  // one write in flight: the limit is reached

  httplib::Client c("127.0.0.1", port);
  const auto refused = c.Put("/v1/test/fast", "{}", "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 503);
  EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
  const Json error = Json::parse(refused->body);
  EXPECT_EQ(error["error"]["code"], "overloaded");
  EXPECT_EQ(writes_done, 0) << "the refused write must not have run";

  const auto read = c.Get("/v1/test/read");  // reads are not admission-controlled
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200);
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_NE(metrics->body.find("anchordb_writes_refused_total 1\n"), std::string::npos) << metrics->body;

  held.Release();
  slow.join();
  EXPECT_EQ(writes_done, 1);
  const auto admitted = c.Put("/v1/test/fast", "{}", "application/json");  // the slot was given back
  ASSERT_TRUE(admitted);
  EXPECT_EQ(admitted->status, 200);
  EXPECT_EQ(writes_done, 2);
  server.stop();
  serving.join();
}

}  // namespace
}  // namespace anchordb::api
