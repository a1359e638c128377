// Keyframe analyses over real HTTP (the anchordb binary on loopback, a real SQLite file): a frame or keyframe
// answers "pending" without waiting; kill -9 with analyses queued, and the restarted server analyses them (in
// keyframe order, before a later keyframe of the map whose request waits for its own analysis); the queue route, the
// metrics and bad input. Deterministic: the first server runs no analysis worker (analysis_threads=0), so its
// analyses are certainly pending at the kill; the second is waited for with wait_for_analysis=true, never by sleeping.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/wall_and_box.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace analysis_queue_http_test {

using nlohmann::json;

// The wall-and-box frames of tests/support/wall_and_box.h, raw little-endian u16 [mm].
std::string Depth(bool box) {
  const std::vector<std::uint16_t> d = testing::WallDepthMm(box);
  return std::string(reinterpret_cast<const char*>(d.data()), d.size() * 2);
}

class AnalysisQueueHttpTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> args = {}) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("queue.sqlite"), std::move(args));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(120, 0);
  }
  void Kill() {
    client_.reset();
    server_->Kill();
    server_.reset();
  }
  json Call(const std::string& method, const std::string& path, const std::string& body, const std::string& type, int status) {
    httplib::Result r = method == "GET" ? client_->Get(path) : client_->Post(path, body, type);
    EXPECT_TRUE(r && r->status == status) << method << " " << path << ": " << (r ? std::to_string(r->status) + " " + r->body : "no response");
    return r ? json::parse(r->body, nullptr, false) : json();
  }
  json Ok(const std::string& method, const std::string& path, const std::string& body = "{}", int status = 200) {
    return Call(method, path, body, "application/json", status);
  }
  json Frame(const std::string& scene, bool box, std::int64_t stamp_ns, const std::string& query = "") {
    return Call("POST", scene + "/frames?stamp=" + std::to_string(stamp_ns) + query, Depth(box), "application/octet-stream", 200);
  }
  std::string OpenScene(std::int64_t stamp_ns) {
    const PinholeIntrinsics K = testing::WallCamera();
    const json camera = {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
    const json pose = {{"position", {0.0, 0.0, 1.0}}, {"orientation", {0.0, 0.0, 0.0, 1.0}}};
    const json opened = Ok("POST", "/v1/maps/home/scenes", json({{"camera", camera}, {"pose", pose}, {"stamp", stamp_ns}}).dump(), 201);
    return "/v1/maps/home/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(AnalysisQueueHttpTest, AnalysesQueuedAtAKillRunAfterTheRestartInKeyframeOrder) {
  Start({"--analysis_threads=0"});
  Ok("POST", "/v1/maps", R"({"id":"home","name":"flat"})", 201);
  const std::string scene = OpenScene(1'000'000'000'000LL);
  std::vector<std::int64_t> keyframes;
  const json begin = Frame(scene, false, 1'000'000'000'100LL);
  ASSERT_TRUE(begin.contains("keyframe")) << begin.dump();
  EXPECT_EQ(begin["analysis"], json({{"state", "pending"}, {"keyframe_id", begin["keyframe"]}}));
  keyframes.push_back(begin["keyframe"]);
  Frame(scene, true, 1'000'000'000'200LL);
  const json added = Ok("POST", scene + "/keyframes", "{}", 201);
  EXPECT_EQ(added["analysis"]["state"], "pending");
  Frame(scene, false, 1'000'000'000'300LL);
  const json closed = Ok("POST", scene + ":close");
  EXPECT_EQ(closed["analysis"]["state"], "pending");
  EXPECT_EQ(Ok("GET", "/v1/maps/home/analysis")["depth"], 3);
  EXPECT_TRUE(Ok("GET", "/v1/maps/home/events")["events"].empty());
  Kill();  // kill -9 with three analyses acknowledged as pending

  Start();  // the default: one worker, which resumes the queue
  const std::string later = OpenScene(2'000'000'000'000LL);
  const json waited = Frame(later, false, 2'000'000'000'100LL, "&wait_for_analysis=true");
  ASSERT_EQ(waited["analysis"]["state"], "done") << waited.dump();
  EXPECT_TRUE(waited["analysis"]["events"].is_array());
  // The map's earlier keyframes were analysed before this one: their events are there, in order.
  const json events = Ok("GET", "/v1/maps/home/events")["events"];
  ASSERT_EQ(events.size(), 2u) << events.dump();
  EXPECT_EQ(events[0]["type"], "added");
  EXPECT_EQ(events[1]["type"], "removed");
  const json queue = Ok("GET", "/v1/maps/home/analysis");
  EXPECT_EQ(queue["depth"], 0);
  EXPECT_EQ(queue["failed"], 0);
  EXPECT_TRUE(queue["oldest_pending_age_s"].is_null());
  httplib::Result metrics = client_->Get("/metrics");
  ASSERT_TRUE(metrics && metrics->status == 200);
  EXPECT_NE(metrics->body.find("anchordb_analysis_done_total 4"), std::string::npos) << metrics->body;
  EXPECT_NE(metrics->body.find("anchordb_analysis_queue_depth 0"), std::string::npos);
}

TEST_F(AnalysisQueueHttpTest, AWaitedKeyframeAnswersItsEventsAndBadInputIsRefused) {
  Start();
  Ok("POST", "/v1/maps", R"({"id":"home","name":"flat"})", 201);
  const std::string scene = OpenScene(1'000'000'000'000LL);
  Frame(scene, false, 1'000'000'000'100LL);
  Frame(scene, true, 1'000'000'000'200LL);
  const json added = Ok("POST", scene + "/keyframes?wait_for_analysis=true", "{}", 201);
  ASSERT_EQ(added["analysis"]["state"], "done") << added.dump();
  ASSERT_EQ(added["analysis"]["events"].size(), 1u);
  EXPECT_EQ(added["analysis"]["events"][0]["type"], "added");
  EXPECT_EQ(added["analysis"]["action_layer"], 0);
  EXPECT_EQ(added["analysis"]["keyframe_id"], added["keyframe"]);
  Frame(scene, false, 1'000'000'000'300LL);
  const json closed = Ok("POST", scene + ":close?wait_for_analysis=1");
  ASSERT_EQ(closed["analysis"]["state"], "done");
  EXPECT_EQ(closed["analysis"]["events"][0]["type"], "removed");
  // Bad values change nothing.
  const std::string other = OpenScene(3'000'000'000'000LL);
  const json refused = Call("POST", other + "/frames?wait_for_analysis=soon", Depth(false), "application/octet-stream", 400);
  EXPECT_EQ(refused["error"]["field"], "wait_for_analysis") << refused.dump();
  EXPECT_EQ(Ok("GET", other)["frames"], 0);
  Ok("POST", other + "/keyframes?wait_for_analysis=perhaps", "{}", 400);
  Ok("GET", "/v1/maps/nowhere/analysis", "", 404);
}

}  // namespace
}  // namespace anchordb
