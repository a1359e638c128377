// Anchored features over real HTTP on loopback (the anchordb binary, a SQLite file): client batches de-duplicated
// on insert, box / radius / time queries, a codebook job, bags of words, refusal of bad input with nothing stored,
// and everything as it was after a restart.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "tests/support/scene_request_json.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"
#include "tests/support/wall_and_box.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace features_http_test {

using nlohmann::json;

class FeaturesHttpTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> args = {}) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("db.sqlite"), std::move(args));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(30, 0);
  }
  void Restart() {
    client_.reset();
    ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
    Start();
  }
  json Post(const std::string& path, const json& body, int expected) {
    auto r = client_->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json Get(const std::string& path, int expected = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json WaitJob(std::int64_t id) {
    for (int i = 0; i < 300; ++i) {
      json j = Get("/v1/jobs/" + std::to_string(id));
      if (j.value("status", "") == "succeeded" || j.value("status", "") == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return {};
  }
  // An x_test feature: descriptor [v, 0, 0, 0] at (x, y, 0).
  static json Item(double v, double x, double y) {
    return {{"descriptor", {v, 0, 0, 0}}, {"anchor_m", {x, y, 0.0}}};
  }

  // Opens a scene facing the wall-and-box scene (camera 1 m up, looking along +x) and posts one raw frame; returns
  // the begin keyframe's id.
  std::int64_t KeyframeOfWallAndBox(const std::string& map = "home") {
    Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
    X_MapCamera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // optical z forward = map x, optical x right = map -y
    X_MapCamera.translation() = Eigen::Vector3d(0, 0, 1);
    const json opened = Post("/v1/maps/" + map + "/scenes", {{"camera", testing::CameraJson(testing::WallCamera())},
                                                      {"pose", testing::PoseJson(X_MapCamera)}, {"stamp", 7000}}, 201);
    const auto depth = testing::WallDepthMm(true);
    auto r = client_->Post("/v1/maps/" + map + "/scenes/" + std::to_string(opened["id"].get<std::int64_t>()) + "/frames?stamp=7000",
                           std::string(reinterpret_cast<const char*>(depth.data()), depth.size() * 2), "application/octet-stream");
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "");
    return json::parse(r->body)["keyframe"].get<std::int64_t>();
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(FeaturesHttpTest, BatchesQueriesCodebookBagOfWordsAndRestart) {
  Start();
  Post("/v1/maps", {{"id", "home"}, {"name", "home"}}, 201);
  // Two clusters of descriptors (0 and 10) in two places; the third item repeats the first (same place, same
  // descriptor): a duplicate. The fourth is at the same place but another descriptor: kept.
  json batch = {{"type", "x_test"}, {"stamp", 1000},
                {"features", {Item(0.0, 0, 0), Item(10.0, 1, 0), Item(0.0, 0.001, 0), Item(10.0, 0, 0)}}};
  json r = Post("/v1/maps/home/features", batch, 200);
  EXPECT_EQ(r["inserted"], 3);
  EXPECT_EQ(r["duplicates"], 1);
  EXPECT_EQ(r["ids"][2], r["ids"][0]);
  EXPECT_EQ(r["duplicate"], json({false, false, true, false}));
  json later = {{"type", "x_test"}, {"stamp", 5000}, {"features", {Item(0.2, 5, 5), Item(10.1, 5, 5.5), Item(9.9, 5.5, 5)}}};
  EXPECT_EQ(Post("/v1/maps/home/features", later, 200)["inserted"], 3);

  EXPECT_EQ(Get("/v1/maps/home/features?type=x_test")["features"].size(), 6u);
  EXPECT_EQ(Get("/v1/maps/home/features?near=0,0,0&radius=0.5")["features"].size(), 2u);
  EXPECT_EQ(Get("/v1/maps/home/features?bbox=4,4,-1,6,6,1")["features"].size(), 3u);
  EXPECT_EQ(Get("/v1/maps/home/features?bbox=4,4,6,6")["features"].size(), 3u);
  EXPECT_EQ(Get("/v1/maps/home/features?since=2000")["features"].size(), 3u);
  EXPECT_EQ(Get("/v1/maps/home/features?until=2000&descriptors=false")["features"][0].contains("descriptor"), false);

  // Bad input: refused with the field named, nothing stored.
  const auto refused = [&](json body, int status, const std::string& field) {
    json e = Post("/v1/maps/home/features", body, status);
    EXPECT_EQ(e["error"]["field"], field) << body.dump();
  };
  refused({{"type", "x_test"}, {"features", {Item(1, 0, 0), {{"descriptor", {1, 2}}, {"anchor_m", {0, 0, 0}}}}}}, 422,
          "features[1].descriptor");  // wrong length for the stored type
  refused({{"type", "fpfh"}, {"features", {Item(1, 0, 0)}}}, 422, "features[0].descriptor");  // fpfh has 33
  refused({{"type", "weird"}, {"features", {Item(1, 0, 0)}}}, 400, "type");
  refused({{"type", "x_test"}, {"features", {{{"descriptor", {1, 2, 3, 4}}, {"anchor_m", {0, 0}}}}}}, 400, "features[0].anchor_m");
  refused({{"type", "x_test"}, {"features", {{{"descriptor", {1, 2, 3, 4}}, {"anchor_m", {0, 0, 0}}, {"keyframe", 77}}}}}, 404,
          "features[0].keyframe");
  auto nan = client_->Post("/v1/maps/home/features",
                           R"({"type":"x_test","features":[{"descriptor":[1,NaN,0,0],"anchor_m":[0,0,0]}]})", "application/json");
  ASSERT_TRUE(nan);
  EXPECT_EQ(nan->status, 400);
  EXPECT_EQ(Get("/v1/maps/home/features")["features"].size(), 6u);
  Get("/v1/maps/home/features?near=0,0,0", 400);
  Get("/v1/maps/home/features?limit=0", 422);
  Get("/v1/maps/nowhere/features", 404);

  // Codebook of 2 words: the 0-ish and the 10-ish descriptors fall into different words.
  Post("/v1/maps/home/codebooks", {{"type", "x_test"}, {"words", 50}}, 422);  // more words than features
  json job = Post("/v1/maps/home/codebooks", {{"type", "x_test"}, {"words", 2}, {"seed", 3}}, 202);
  json done = WaitJob(job["job"].get<std::int64_t>());
  ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  json book = Get("/v1/maps/home/codebooks/x_test?centres=true");
  EXPECT_EQ(book["words"], 2);
  EXPECT_EQ(book["centres"].size(), 8u);
  const json features = Get("/v1/maps/home/features?type=x_test")["features"];
  std::map<int, int> word_of_cluster;
  for (const json& f : features) {
    const int cluster = f["descriptor"][0].get<double>() > 5 ? 1 : 0;
    ASSERT_TRUE(f["codeword"].is_number());
    if (!word_of_cluster.count(cluster)) word_of_cluster[cluster] = f["codeword"];
    EXPECT_EQ(f["codeword"], word_of_cluster[cluster]);
  }
  ASSERT_EQ(word_of_cluster.size(), 2u);
  EXPECT_NE(word_of_cluster[0], word_of_cluster[1]);
  // A feature added after the codebook gets its codeword on insert.
  Post("/v1/maps/home/features", {{"type", "x_test"}, {"stamp", 6000}, {"features", {Item(9.5, 5.2, 5.2)}}}, 200);
  EXPECT_EQ(Get("/v1/maps/home/features?since=6000")["features"][0]["codeword"], word_of_cluster[1]);

  // Bag of words of the place around (5, 5): one 0-ish, three 10-ish features.
  json bow = Get("/v1/maps/home/bow?type=x_test&polygon=4,4;6,4;6,6;4,6");
  EXPECT_EQ(bow["features"], 4);
  EXPECT_DOUBLE_EQ(bow["histogram"][word_of_cluster[0]].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(bow["histogram"][word_of_cluster[1]].get<double>(), 0.75);
  EXPECT_EQ(Get("/v1/maps/home/bow?type=x_test&near=5,5,0&radius=1")["features"], 4);
  Get("/v1/maps/home/bow?type=x_test", 400);                                  // no region
  Get("/v1/maps/home/bow?type=x_test&polygon=0,0;1,1&near=0,0,0&radius=1", 400);  // two regions
  Get("/v1/maps/home/bow?type=shot&near=0,0,0&radius=1", 404);                 // no codebook

  Restart();
  EXPECT_EQ(Get("/v1/maps/home/features")["features"].size(), 7u);
  EXPECT_EQ(Get("/v1/maps/home/codebooks/x_test?centres=true")["centres"], book["centres"]);
  EXPECT_EQ(Get("/v1/maps/home/bow?type=x_test&polygon=4,4;6,4;6,6;4,6")["histogram"], bow["histogram"]);
}


TEST_F(FeaturesHttpTest, ServerSideExtractionIsDeduplicatedAndCanRunForEveryKeyframe) {
  Start();
  Post("/v1/maps", {{"id", "home"}, {"name", "home"}}, 201);
  const std::int64_t kf = KeyframeOfWallAndBox();
  const std::string path = "/v1/maps/home/keyframes/" + std::to_string(kf) + ":extract";
  const json first = Post(path, json::object(), 200);
  std::map<std::string, int> inserted;
  for (const json& t : first["types"]) inserted[t["type"]] = t["inserted"];
  EXPECT_GT(inserted["fpfh"], 10);
  EXPECT_EQ(inserted["fpfh"], inserted["shot"]);
  EXPECT_GE(inserted["spd"], 1);  // the wall (the box face is under the plane size limit or a second plane)
  const json features = Get("/v1/maps/home/features?keyframe=" + std::to_string(kf) + "&type=spd")["features"];
  ASSERT_FALSE(features.empty());
  EXPECT_NEAR(features[0]["anchor_m"][0].get<double>(), 2.0, 0.05);  // the wall, 2 m ahead
  EXPECT_EQ(features[0]["stamp"], 7000);
  EXPECT_EQ(features[0]["descriptor"].size(), 8u);
  // The same keyframe again: every feature is a duplicate of one stored.
  const json again = Post(path, json::object(), 200);
  for (const json& t : again["types"]) {
    EXPECT_EQ(t["inserted"], 0) << t.dump();
    EXPECT_EQ(t["duplicates"], t["extracted"]);
  }
  EXPECT_EQ(Post(path, {{"types", {"orb"}}}, 400)["error"]["field"], "types");
  Post("/v1/maps/home/keyframes/999:extract", json::object(), 404);

  // With the setting on, the keyframe of a new scene gets its features without being asked (in another map: here
  // they would all be duplicates of those above).
  client_.reset();
  ASSERT_EQ(server_->Stop(), 0);
  server_.reset();
  Start({"--features_extract_every_keyframe=true"});
  Post("/v1/maps", {{"id", "flat"}, {"name", "flat"}}, 201);
  const std::int64_t automatic = KeyframeOfWallAndBox("flat");
  json found;
  for (int i = 0; i < 200 && found.empty(); ++i) {
    found = Get("/v1/maps/flat/features?type=fpfh&keyframe=" + std::to_string(automatic))["features"];
    if (found.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_FALSE(found.empty());
}

}  // namespace
}  // namespace anchordb
