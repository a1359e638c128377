// Furniture graphs over real HTTP on loopback (the anchordb binary, a SQLite file): a conversation interrupted by a
// restart (graceful, and kill -9) ends with the same graph as an uninterrupted one; bad input is refused with an
// error naming what was not understood and leaves the hypotheses as they were; the room prior finds the map's
// occupancy layer by itself.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace furniture_http_test {

using nlohmann::json;

json LivingRoom() {
  return json::parse(R"({
    "viewpoint": {"position": [0, 0], "heading_rad": 0},
    "furniture": [
      {"id": "sofa", "position": [4.0, 0.0], "extent": [0.9, 2.0], "categories": {"sofa": 0.6, "armchair": 0.3, "table": 0.1}},
      {"id": "plant", "position": [4.0, 1.7], "extent": [0.4, 0.4], "categories": {"plant": 0.7, "stool": 0.3}},
      {"id": "table", "position": [2.8, 0.0], "extent": [0.6, 1.0], "categories": {"table": 0.6, "stool": 0.2, "chair": 0.2}},
      {"id": "armchair", "position": [2.8, -1.5], "extent": [0.8, 0.8], "categories": {"armchair": 0.5, "sofa": 0.3, "chair": 0.2}},
      {"id": "shelf", "position": [4.2, -1.6], "extent": [0.4, 1.0], "categories": {"armchair": 0.45, "shelf": 0.35, "wardrobe": 0.2}},
      {"id": "stool", "position": [2.8, 1.5], "extent": [0.4, 0.4], "categories": {"stool": 0.6, "plant": 0.2, "chair": 0.2}}
    ],
    "params": {"n_best": 100}
  })");
}

const std::vector<json>& Conversation() {
  static const std::vector<json> kDescriptions = {
      {{"text", "the plant is left of the sofa"}},
      {{"located", "table"}, {"relation", "in_front_of"}, {"reference", "sofa"}},
      {{"text", "behind the armchair is the shelf"}},
      {{"text", "the shelf is to the right of the couch"}},
      {{"located", "stool"}, {"relation", "left of"}, {"reference", "table"}},
      {{"text", "the armchair is right of the table"}},
      {{"text", "the sofa is behind the table"}},
      {{"text", "the table is to the right of the stool"}},
      {{"text", "in front of the plant is the stool"}},
      {{"text", "the shelf is behind the armchair"}},
  };
  return kDescriptions;
}

class FurnitureHttpTest : public ::testing::Test {
 protected:
  void Start(const std::string& db) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File(db));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(30, 0);
  }
  void Stop(bool crash) {
    client_.reset();
    if (crash) server_->Kill();
    else ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
  }
  httplib::Result PostRaw(const std::string& path, const json& body) { return client_->Post(path, body.dump(), "application/json"); }
  json Post(const std::string& path, const json& body, int expected) {
    auto r = PostRaw(path, body);
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json Get(const std::string& path) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path << (r ? r->body : "");
    return r ? json::parse(r->body, nullptr, false) : json();
  }
  std::string NewGraph() {
    Post("/v1/maps", {{"id", "home"}, {"name", "Home"}}, 201);
    const json g = Post("/v1/maps/home/furniture-graphs", LivingRoom(), 201);
    return "/v1/maps/home/furniture-graphs/" + std::to_string(g.value("id", 0));
  }
  // The served graph without its time stamps.
  json Final(const std::string& graph) {
    json g = Get(graph);
    g.erase("created_ns");
    g.erase("updated_ns");
    return g;
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;  // NOLINT
  std::unique_ptr<httplib::Client> client_;
};

// A room 5 m x 5 m (walls two cells thick) as the map's only occupancy layer, "walls": a graph that names no layer
// takes it, and the shelf with its back to the east wall faces into the room (towards the viewer: "front").
TEST_F(FurnitureHttpTest, TheRoomPriorUsesTheMapsOccupancyLayerWhenNoneIsNamed) {
  Start("room.sqlite");
  const int cells = 100;  // 0.05 m: x 0-5 m, y -2.5-2.5 m
  std::string pgm = "P5\n100 100\n255\n";
  for (int row = 0; row < cells; ++row) {
    for (int col = 0; col < cells; ++col) {
      const bool wall = row < 2 || col < 2 || row >= cells - 2 || col >= cells - 2;
      pgm += static_cast<char>(wall ? 0 : 254);
    }
  }
  const std::string yaml = "image: walls.pgm\nresolution: 0.05\norigin: [0.0, -2.5, 0.0]\nnegate: 0\n"
                           "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const json body = json::parse(R"({
    "viewpoint": {"position": [0.5, 0], "heading_rad": 0},
    "furniture": [
      {"id": "shelf", "position": [4.65, 0.0], "extent": [0.4, 1.0], "yaw_rad": 3.14159, "categories": {"shelf": 0.8, "table": 0.2}},
      {"id": "plant", "position": [3.8, 0.9], "extent": [0.4, 0.4], "categories": {"plant": 0.8, "stool": 0.2}}
    ]
  })");
  for (const char* map : {"home", "bare"}) Post("/v1/maps", {{"id", map}, {"name", map}}, 201);
  auto layer = client_->Put("/v1/maps/home/layers/walls",
                            httplib::MultipartFormDataItems{{"yaml", yaml, "walls.yaml", "text/yaml"},
                                                            {"image", pgm, "walls.pgm", "image/x-portable-graymap"}});
  ASSERT_TRUE(layer && layer->status / 100 == 2) << (layer ? layer->body : "");
  const json g = Post("/v1/maps/home/furniture-graphs", body, 201);
  EXPECT_EQ(g["params"]["occupancy_layer"], "walls") << g.dump();
  ASSERT_EQ(g["vertices"][0]["id"], "shelf");
  EXPECT_GE(g["vertices"][0]["orientations"]["front"].get<double>(), 0.7) << g["vertices"][0].dump();
  // A map without an occupancy layer: no walls, so the shelf's front stays unknown.
  const json bare = Post("/v1/maps/bare/furniture-graphs", body, 201);
  EXPECT_TRUE(bare["params"]["occupancy_layer"].is_null()) << bare.dump();
  EXPECT_LT(bare["vertices"][0]["orientations"]["front"].get<double>(), 0.5);
}

TEST_F(FurnitureHttpTest, RestartInTheMiddleOfASequenceGivesTheSameFinalGraph) {
  Start("straight.sqlite");
  const std::string graph = NewGraph();
  for (const json& d : Conversation()) Post(graph + "/descriptions", d, 201);
  const json straight = Final(graph);
  const json straight_hypotheses = Get(graph + "/hypotheses?limit=100");
  Stop(false);
  ASSERT_EQ(straight["descriptions"], Conversation().size());
  EXPECT_EQ(straight["vertices"][4]["label"], "shelf");  // seen as an armchair, corrected by the descriptions

  for (const bool crash : {false, true}) {
    SCOPED_TRACE(crash ? "kill -9" : "graceful stop");
    Start(crash ? "crashed.sqlite" : "restarted.sqlite");
    const std::string g = NewGraph();
    for (std::size_t i = 0; i < 4; ++i) Post(g + "/descriptions", Conversation()[i], 201);
    Stop(crash);
    Start(crash ? "crashed.sqlite" : "restarted.sqlite");
    EXPECT_EQ(Get(g)["descriptions"], 4);
    for (std::size_t i = 4; i < Conversation().size(); ++i) Post(g + "/descriptions", Conversation()[i], 201);
    EXPECT_EQ(Final(g), straight);
    EXPECT_EQ(Get(g + "/hypotheses?limit=100"), straight_hypotheses);
    Stop(false);
  }
}

TEST_F(FurnitureHttpTest, BadInputIsRefusedNamingWhatWasNotUnderstoodAndChangesNothing) {
  Start("bad.sqlite");
  const std::string graph = NewGraph();
  Post(graph + "/descriptions", Conversation()[0], 201);
  const json before = Get(graph + "/hypotheses?limit=1000");
  const json graph_before = Final(graph);
  struct Case {
    json body;
    int status;
    const char* field;
    const char* named;
  };
  const Case cases[] = {
      {{{"text", "the bed is left of the sofa"}}, 422, "text", "'bed'"},
      {{{"located", "bed"}, {"relation", "left_of"}, {"reference", "sofa"}}, 422, "located", "'bed'"},
      {{{"located", "plant"}, {"relation", "under"}, {"reference", "sofa"}}, 422, "relation", "'under'"},
      {{{"text", "the plant is next to the sofa"}}, 422, "text", "'next to'"},
      {{{"text", "sofa the plant left of"}}, 422, "text", "does not parse"},
      {{{"text", "the plant is left of"}}, 422, "text", "two pieces"},
      {{{"located", "plant"}, {"reference", "sofa"}}, 400, "relation", "relation"},
  };
  for (const Case& c : cases) {
    const json e = Post(graph + "/descriptions", c.body, c.status);
    ASSERT_TRUE(e.contains("error")) << e.dump();
    EXPECT_EQ(e["error"]["field"], c.field) << e.dump();
    EXPECT_NE(e["error"]["message"].get<std::string>().find(c.named), std::string::npos) << e.dump();
  }
  auto r = client_->Post(graph + "/descriptions", "{not json", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(Get(graph + "/hypotheses?limit=1000"), before);
  EXPECT_EQ(Final(graph), graph_before);
  // An empty graph and a graph without edges cannot be built; unknown graphs are 404.
  json empty = LivingRoom();
  empty["furniture"] = json::array();
  EXPECT_NE(Post("/v1/maps/home/furniture-graphs", empty, 422)["error"]["message"].get<std::string>().find("at least two"), std::string::npos);
  json apart = LivingRoom();
  apart["furniture"] = json::array({LivingRoom()["furniture"][0], LivingRoom()["furniture"][1]});
  apart["furniture"][1]["position"] = {30.0, 30.0};
  EXPECT_NE(Post("/v1/maps/home/furniture-graphs", apart, 422)["error"]["message"].get<std::string>().find("no edges"), std::string::npos);
  Post("/v1/maps/home/furniture-graphs/999/descriptions", Conversation()[0], 404);
  Post("/v1/maps/home/furniture-graphs/abc:reset", json::object(), 404);
}

TEST_F(FurnitureHttpTest, HypothesesSpeechProductionAndReset) {
  Start("routes.sqlite");
  const std::string graph = NewGraph();
  json last;
  for (const json& d : Conversation()) last = Post(graph + "/descriptions", d, 201);
  EXPECT_EQ(last["seq"], Conversation().size());
  EXPECT_EQ(last["understood"]["located"], "shelf");
  EXPECT_EQ(last["groundings"].size(), Conversation().size());
  const json h = Get(graph + "/hypotheses?limit=5");
  EXPECT_EQ(h["count"], 100);
  ASSERT_EQ(h["hypotheses"].size(), 5u);
  EXPECT_EQ(h["hypotheses"][0]["rank"], 1);
  EXPECT_EQ(h["hypotheses"][0]["ancestor_ranks"].size(), Conversation().size());
  auto bad_limit = client_->Get(graph + "/hypotheses?limit=0");
  ASSERT_TRUE(bad_limit);
  EXPECT_EQ(bad_limit->status, 422);
  const json said = Post(graph + ":describe", {{"located", "plant"}, {"reference", "sofa"}}, 200);
  EXPECT_EQ(said["sentence"], "the plant is to the left of the sofa");
  const json listed = Get("/v1/maps/home/furniture-graphs");
  EXPECT_EQ(listed["furniture_graphs"].size(), 1u);
  const json reset = Post(graph + ":reset", json::object(), 200);
  EXPECT_EQ(reset["descriptions"], 0);
  EXPECT_EQ(Get(graph + "/hypotheses")["count"], 1);
}

}  // namespace
}  // namespace anchordb
