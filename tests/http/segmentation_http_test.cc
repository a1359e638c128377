// Furniture segmentation over real HTTP on loopback (the anchordb binary, a SQLite file) with rendered depth frames
// of the furnished room (sim/apartment_furnished.h): the job turns the keyframes into furniture instances, leaves
// an operator's piece alone, updates what it finds again, keeps everything over a restart, builds a furniture graph
// from what it found, and refuses bad input with an error naming the field.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "engine/cloud/cloud_io.h"
#include "engine/segmentation/footprint.h"
#include "sim/apartment_furnished.h"
#include "sim/scenario_driver.h"

namespace anchordb {
namespace segmentation_http_test {

using nlohmann::json;

class SegmentationHttpTest : public ::testing::Test {
 protected:
  void Start() {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("db.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  void Restart() {
    client_.reset();
    ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
    Start();
  }
  json Call(const std::string& method, const std::string& path, const json& body, int expected) {
    httplib::Result r = method == "GET" ? client_->Get(path) : client_->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r) << method << " " << path;
    if (!r) return json();
    EXPECT_EQ(r->status, expected) << method << " " << path << ": " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json Error(const std::string& method, const std::string& path, const json& body, int expected, const std::string& field) {
    const json e = Call(method, path, body, expected);
    EXPECT_EQ(e["error"]["field"], field) << e.dump();
    EXPECT_FALSE(e["error"]["message"].get<std::string>().empty());
    return e;
  }
  json AwaitJob(const json& ticket) {
    const std::string path = "/v1/jobs/" + std::to_string(ticket["job"].get<std::int64_t>());
    for (int i = 0; i < 600; ++i) {
      const json j = Call("GET", path, json(), 200);
      const std::string status = j.value("status", "");
      if (status == "succeeded" || status == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "job did not finish";
    return json();
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(SegmentationHttpTest, KeyframesBecomeFurnitureThatSurvivesARestart) {
  Start();
  const sim::FurnishedRoom room = sim::MakeFurnishedRoom(5);
  Call("POST", "/v1/maps", {{"id", "flat"}, {"name", "furnished room"}}, 201);
  // The operator entered the wardrobe (as a cupboard, on purpose): the segmentation must leave it so.
  const sim::PlacedPiece& wardrobe = room.pieces[4];
  const json entered = Call("POST", "/v1/maps/flat/instances",
                            {{"kind", "furniture"}, {"label", "cupboard"}, {"position", {wardrobe.centre_m.x(), wardrobe.centre_m.y(), 1.0}},
                             {"extent", {wardrobe.extent_m.x(), wardrobe.extent_m.y(), 2.0}}, {"yaw_rad", wardrobe.yaw_rad}}, 201);
  const std::int64_t operator_id = entered["id"];
  {
    sim::ScenarioDriver d(*client_, "flat", nullptr);
    std::int64_t t = 1'767'225'600'000'000'000;
    for (std::size_t v = 0; v < room.X_WorldCamera.size(); ++v, t += 60'000'000'000LL) {
      d.Observe("view " + std::to_string(v), room.X_WorldCamera[v], room.X_WorldCamera[v], 3,
                [&](int) { return std::make_pair(room.scene, false); }, t, 100 + v);
    }
  }
  // Bad input: nothing queued.
  Error("POST", "/v1/maps/flat/furniture:segment", {{"max_range_m", -1}}, 422, "max_range_m");
  Error("POST", "/v1/maps/flat/furniture:segment", {{"params", {{"voxel_m", 0}}}}, 400, "params.voxel_m");
  Error("POST", "/v1/maps/flat/furniture:segment", {{"params", {{"voxel", 0.1}}}}, 400, "params.voxel");
  Error("POST", "/v1/maps/flat/furniture:segment", {{"source", "moon"}}, 400, "source");
  Error("POST", "/v1/maps/flat/furniture:segment", {{"keyframes", {1, "two"}}}, 400, "keyframes[1]");
  Error("POST", "/v1/maps/flat/furniture:segment", {{"shape_model", "nope"}}, 404, "shape_model");
  Error("POST", "/v1/maps/nowhere/furniture:segment", json::object(), 404, "map");
  const json failed = AwaitJob(Call("POST", "/v1/maps/flat/furniture:segment", {{"keyframes", {999999}}}, 202));
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(Call("GET", "/v1/maps/flat/furniture", json(), 200)["furniture"].size(), 1u);  // the operator's only

  const json job = AwaitJob(Call("POST", "/v1/maps/flat/furniture:segment", json::object(), 202));
  ASSERT_EQ(job["status"], "succeeded") << job.dump();
  const json& result = job["result"];
  int created = 0, kept = 0;
  std::int64_t table_id = 0;
  for (const json& s : result["segments"]) {
    const std::string action = s["action"];
    created += action == "created";
    if (action == "kept_operator") {
      ++kept;
      EXPECT_EQ(s["furniture"], operator_id);
    }
    engine::segmentation::Footprint f;
    f.centre_m = Eigen::Vector2d(s["position_m"][0], s["position_m"][1]);
    f.extent_m = Eigen::Vector2d(s["extent_m"][0], s["extent_m"][1]);
    f.yaw_rad = s["yaw_rad"];
    engine::segmentation::Footprint table;
    table.centre_m = room.pieces[static_cast<std::size_t>(room.table_index)].centre_m;
    table.extent_m = room.pieces[static_cast<std::size_t>(room.table_index)].extent_m;
    table.yaw_rad = room.pieces[static_cast<std::size_t>(room.table_index)].yaw_rad;
    if (engine::segmentation::FootprintIoU(f, table) >= 0.5) {
      table_id = s["furniture"];
      EXPECT_EQ(s["label"], "table");
      EXPECT_NEAR(s["height_m"].get<double>(), 0.75, 0.08);
    }
  }
  EXPECT_EQ(kept, 1);
  EXPECT_GE(created, 4);
  ASSERT_GT(table_id, 0);
  // The operator's piece is as entered.
  const json op = Call("GET", "/v1/maps/flat/furniture/" + std::to_string(operator_id), json(), 200);
  EXPECT_FALSE(op["perceived"]);
  EXPECT_EQ(op["label"], "cupboard");
  EXPECT_EQ(op["classifier"], "operator");
  Error("GET", "/v1/maps/flat/furniture/" + std::to_string(operator_id) + "/cloud", json(), 422, "furniture");
  Error("GET", "/v1/maps/flat/furniture/999999", json(), 404, "furniture");
  // The table's cloud, its evidence keyframes and its p(f).
  const json table = Call("GET", "/v1/maps/flat/furniture/" + std::to_string(table_id), json(), 200);
  EXPECT_TRUE(table["perceived"]);
  EXPECT_FALSE(table["evidence"].empty());
  for (const json& k : table["evidence"]) Call("GET", "/v1/maps/flat/keyframes/" + std::to_string(k.get<std::int64_t>()), json(), 200);
  const auto cloud = client_->Get("/v1/maps/flat/furniture/" + std::to_string(table_id) + "/cloud?format=ply");
  ASSERT_TRUE(cloud);
  ASSERT_EQ(cloud->status, 200);
  const engine::DecodedCloud decoded = engine::DecodeCloud(cloud->body, 10'000'000);
  EXPECT_EQ(static_cast<std::int64_t>(decoded.points.size()), table["points"].get<std::int64_t>());
  EXPECT_GT(decoded.points.size(), 100u);

  // A restart keeps every piece as it was.
  const json before = Call("GET", "/v1/maps/flat/furniture", json(), 200);
  Restart();
  EXPECT_EQ(Call("GET", "/v1/maps/flat/furniture", json(), 200), before);

  // The graph of what the robot found, seen from the room's middle: the table is a vertex labelled table.
  Error("POST", "/v1/maps/flat/furniture-graphs",
        {{"viewpoint", {{"position", {0.0, 0.0}}, {"heading_rad", 0.0}}}, {"from_instances", true}, {"furniture", json::array()}}, 400, "furniture");
  const json graph = Call("POST", "/v1/maps/flat/furniture-graphs",
                          {{"viewpoint", {{"position", {-1.5, -1.5}}, {"heading_rad", 0.6}}}, {"from_instances", true}}, 201);
  bool table_vertex = false;
  for (const json& v : graph["vertices"]) {
    if (v["id"] == "f" + std::to_string(table_id)) table_vertex = v["label"] == "table";
  }
  EXPECT_TRUE(table_vertex) << graph.dump();
  EXPECT_EQ(graph["vertices"].size(), before["furniture"].size());

  // Found again: the same instances, updated.
  const json again = AwaitJob(Call("POST", "/v1/maps/flat/furniture:segment", json::object(), 202));
  ASSERT_EQ(again["status"], "succeeded");
  bool table_updated = false;
  for (const json& s : again["result"]["segments"]) {
    if (s["furniture"] == table_id) table_updated = s["action"] == "updated";
  }
  EXPECT_TRUE(table_updated);
  EXPECT_EQ(Call("GET", "/v1/maps/flat/furniture/" + std::to_string(table_id), json(), 200)["observations"], 2);
  EXPECT_EQ(Call("GET", "/v1/maps/flat/furniture", json(), 200)["furniture"].size(), before["furniture"].size());
}

}  // namespace
}  // namespace anchordb
