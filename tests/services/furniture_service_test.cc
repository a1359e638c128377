// FurnitureService without HTTP: a conversation grounded against a furniture graph, a restart in the middle that
// continues identically, bad input refused with the hypotheses unchanged, reset, speech production, the codec.
#include "services/furniture/furniture_service.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/repositories.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace {

// A living room seen from the door (map +x is the viewing direction, map +y the viewer's left).
Json LivingRoom() {
  return Json::parse(R"({
    "viewpoint": {"position": [0, 0], "heading_rad": 0},
    "furniture": [
      {"id": "sofa", "position": [4.0, 0.0], "extent": [0.9, 2.0], "categories": {"sofa": 0.6, "armchair": 0.3, "table": 0.1}},
      {"id": "plant", "position": [4.0, 1.7], "extent": [0.4, 0.4], "categories": {"plant": 0.7, "stool": 0.3}},
      {"id": "table", "position": [2.8, 0.0], "extent": [0.6, 1.0], "categories": {"table": 0.6, "stool": 0.2, "chair": 0.2}},
      {"id": "armchair", "position": [2.8, -1.5], "extent": [0.8, 0.8], "categories": {"armchair": 0.5, "sofa": 0.3, "chair": 0.2}},
      {"id": "shelf", "position": [4.2, -1.6], "extent": [0.4, 1.0], "categories": {"armchair": 0.45, "shelf": 0.35, "wardrobe": 0.2}},
      {"id": "stool", "position": [2.8, 1.5], "extent": [0.4, 0.4], "categories": {"stool": 0.6, "plant": 0.2, "chair": 0.2}}
    ],
    "params": {"n_best": 100, "sigma": 3}
  })");
}

const std::vector<Json>& Conversation() {
  static const std::vector<Json> kDescriptions = {
      {{"text", "the plant is left of the sofa"}},
      {{"located", "table"}, {"relation", "in_front_of"}, {"reference", "sofa"}},
      {{"text", "behind the armchair is the shelf"}},
      {{"text", "the shelf is to the right of the couch"}},
      {{"located", "stool"}, {"relation", "left of"}, {"reference", "table"}},
      {{"text", "the armchair is right of the table"}},
      {{"text", "the sofa is behind the table"}},
      {{"text", "the table is to the right of the stool"}},
  };
  return kDescriptions;
}

class FurnitureServiceTest : public ::testing::Test {
 protected:
  void Open() {
    storage::StoreOptions so;
    so.path = dir_.File("graphs.sqlite");
    store_ = std::make_unique<storage::Store>(so);
    service_ = std::make_unique<FurnitureService>(*store_, FurnitureSettings{});
  }
  void Close() {
    service_.reset();
    store_.reset();
  }
  void SetUp() override {
    Open();
    store_->Write([](storage::Connection& c) { storage::InsertMap(c, {"home", "Home", 1}); });
  }
  // The graph as served, without the time stamps that differ between runs.
  Json Stable(Json j) {
    j.erase("created_ns");
    j.erase("updated_ns");
    return j;
  }

  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<FurnitureService> service_;
};

TEST_F(FurnitureServiceTest, GroundsAConversationAndCorrectsTheMisclassifiedShelf) {
  const Json created = service_->Create("home", LivingRoom());
  const std::int64_t id = created["id"];
  EXPECT_EQ(created["descriptions"], 0);
  EXPECT_EQ(created["best"]["scheme"], "none");
  EXPECT_GE(created["edges"].size(), 6u);
  for (const Json& d : Conversation()) {
    const Json r = service_->Describe("home", id, d);
    EXPECT_TRUE(r.contains("match"));
  }
  const Json g = service_->Get("home", id);
  EXPECT_EQ(g["descriptions"], 8);
  ASSERT_EQ(g["groundings"].size(), 8u);
  const char* expected[8][2] = {{"plant", "sofa"}, {"table", "sofa"}, {"shelf", "armchair"}, {"shelf", "sofa"},
                                {"stool", "table"}, {"armchair", "table"}, {"sofa", "table"}, {"table", "stool"}};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(g["groundings"][i]["located"], expected[i][0]) << i;
    EXPECT_EQ(g["groundings"][i]["reference"], expected[i][1]) << i;
  }
  EXPECT_EQ(g["groundings"][0]["understood"]["located"], "plant");
  EXPECT_EQ(g["groundings"][3]["input"]["text"], "the shelf is to the right of the couch");
  // The shelf was seen as an armchair; the descriptions relabel it.
  for (const Json& v : g["vertices"]) EXPECT_EQ(v["label"], v["id"]) << v.dump();
}

TEST_F(FurnitureServiceTest, RestartInTheMiddleContinuesIdentically) {
  // Uninterrupted.
  const std::int64_t a = service_->Create("home", LivingRoom())["id"];
  for (const Json& d : Conversation()) service_->Describe("home", a, d);
  const Json final_a = Stable(service_->Get("home", a));
  const Json hyps_a = service_->Hypotheses("home", a, 1000);
  // Interrupted after 3 descriptions: the service and the database are closed and reopened.
  const std::int64_t b = service_->Create("home", LivingRoom())["id"];
  for (std::size_t i = 0; i < 3; ++i) service_->Describe("home", b, Conversation()[i]);
  Close();
  Open();
  for (std::size_t i = 3; i < Conversation().size(); ++i) service_->Describe("home", b, Conversation()[i]);
  Json final_b = Stable(service_->Get("home", b));
  Json hyps_b = service_->Hypotheses("home", b, 1000);
  final_b["id"] = a;
  hyps_b["graph"] = a;
  EXPECT_EQ(final_a, final_b);
  // Hypothesis ids are per graph and therefore equal too.
  EXPECT_EQ(hyps_a, hyps_b);
  EXPECT_EQ(hyps_a["count"], 100);
}

Json ExpectError(const std::function<void()>& f, ErrorCode code, const std::string& field, const std::string& word) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error (expected one naming " << word << ")";
  return {};
}

TEST_F(FurnitureServiceTest, BadInputIsRefusedAndLeavesTheHypothesesUnchanged) {
  const std::int64_t id = service_->Create("home", LivingRoom())["id"];
  service_->Describe("home", id, Conversation()[0]);
  const Json before = service_->Hypotheses("home", id, 1000);
  const Json graph_before = Stable(service_->Get("home", id));
  auto describe = [&](const Json& body) { return [this, id, body] { service_->Describe("home", id, body); }; };
  ExpectError(describe({{"text", "the bed is left of the sofa"}}), ErrorCode::kUnprocessable, "text", "'bed'");
  ExpectError(describe({{"located", "bed"}, {"relation", "left_of"}, {"reference", "sofa"}}), ErrorCode::kUnprocessable, "located", "'bed'");
  ExpectError(describe({{"located", "plant"}, {"relation", "next_to"}, {"reference", "sofa"}}), ErrorCode::kUnprocessable, "relation", "'next_to'");
  ExpectError(describe({{"text", "the plant is next to the sofa"}}), ErrorCode::kUnprocessable, "text", "'next to'");
  ExpectError(describe({{"text", "sofa plant left of"}}), ErrorCode::kUnprocessable, "text", "does not parse");
  ExpectError(describe({{"text", "the plant"}, {"relation", "left_of"}}), ErrorCode::kInvalidArgument, "text", "either");
  ExpectError(describe({{"located", "plant"}, {"reference", "sofa"}}), ErrorCode::kInvalidArgument, "relation", "relation");
  ExpectError(describe({{"txt", "the plant is left of the sofa"}}), ErrorCode::kInvalidArgument, "txt", "txt");
  EXPECT_EQ(service_->Hypotheses("home", id, 1000), before);
  EXPECT_EQ(Stable(service_->Get("home", id)), graph_before);
  // An empty graph, a graph without edges, unknown category words in the furniture: refused at creation.
  Json empty = LivingRoom();
  empty["furniture"] = Json::array();
  ExpectError([&] { service_->Create("home", empty); }, ErrorCode::kUnprocessable, "furniture", "at least two");
  Json apart = LivingRoom();
  apart["furniture"] = Json::array({LivingRoom()["furniture"][0], LivingRoom()["furniture"][1]});
  apart["furniture"][1]["position"] = {40.0, 40.0};
  ExpectError([&] { service_->Create("home", apart); }, ErrorCode::kUnprocessable, "furniture", "no edges");
  Json bed = LivingRoom();
  bed["furniture"][2]["categories"] = {{"bed", 1.0}};
  ExpectError([&] { service_->Create("home", bed); }, ErrorCode::kUnprocessable, "furniture[2].categories.bed", "'bed'");
  Json sigma = LivingRoom();
  sigma["params"]["sigma"] = 0.5;
  ExpectError([&] { service_->Create("home", sigma); }, ErrorCode::kUnprocessable, "params.sigma", "sigma");
  ExpectError([&] { service_->Get("home", 999); }, ErrorCode::kNotFound, "graph", "999");
  ExpectError([&] { service_->Get("nowhere", id); }, ErrorCode::kNotFound, "graph", "nowhere");
}

TEST_F(FurnitureServiceTest, ResetAndSpeechProduction) {
  const std::int64_t id = service_->Create("home", LivingRoom())["id"];
  for (const Json& d : Conversation()) service_->Describe("home", id, d);
  // The listener names the shelf a shelf (it was seen as an armchair) and says "right of the sofa".
  const Json said = service_->Produce("home", id, {{"located", "shelf"}, {"reference", "sofa"}});
  EXPECT_EQ(said["located"]["label"], "shelf");
  EXPECT_EQ(said["reference"]["label"], "sofa");
  EXPECT_EQ(said["relation"], "right_of");
  EXPECT_EQ(said["sentence"], "the shelf is to the right of the sofa");
  EXPECT_EQ(said["alternatives"].size(), 4u);
  ExpectError([&] { service_->Produce("home", id, {{"located", "plant"}, {"reference", "armchair"}}); }, ErrorCode::kUnprocessable, "",
              "share no edge");
  ExpectError([&] { service_->Produce("home", id, {{"located", "ghost"}, {"reference", "sofa"}}); }, ErrorCode::kNotFound, "located", "ghost");
  const Json reset = service_->Reset("home", id);
  EXPECT_EQ(reset["descriptions"], 0);
  EXPECT_EQ(reset["groundings"].size(), 0u);
  EXPECT_EQ(service_->Hypotheses("home", id, 10)["count"], 1);
  EXPECT_EQ(service_->Get("home", id)["vertices"][4]["label"], "armchair");  // as seen again
  const Json listed = service_->List("home", 0, 10);
  EXPECT_EQ(listed["furniture_graphs"].size(), 1u);
}

TEST_F(FurnitureServiceTest, CodecRoundTripsAndRejectsCorruption) {
  namespace g = engine::grounding;
  const g::Knowledge& k = g::DefaultKnowledge();
  const std::vector<double> pf(10, 0.1);
  const g::FurnitureGraph graph = g::BuildFurnitureGraph(
      {{0, 0}, 0}, {{"a", {2, 0}, {0.5, 0.5}, 0, pf}, {"b", {2, 1}, {0.5, 0.5}, 0, pf}, {"c", {3, 0}, {0.5, 0.5}, 0, pf}}, 10, {});
  g::GroundingParams params;
  params.n_best = 7;
  g::HypothesisSet set = g::InitialHypotheses(graph);
  set = g::Ground(graph, k, set, {0, g::Relation::kLeftOf, 1}, params);
  set = g::Ground(graph, k, set, {2, g::Relation::kBehind, 0}, params);
  const g::HypothesisSet back = DecodeHypotheses(graph, EncodeHypotheses(graph, set));
  ASSERT_EQ(back.ranked.size(), set.ranked.size());
  EXPECT_EQ(back.step, 2);
  EXPECT_EQ(back.next_id, set.next_id);
  for (std::size_t i = 0; i < set.ranked.size(); ++i) {
    EXPECT_EQ(back.ranked[i].id, set.ranked[i].id);
    EXPECT_EQ(back.ranked[i].score, set.ranked[i].score);
    EXPECT_EQ(back.ranked[i].scheme, set.ranked[i].scheme);
    EXPECT_EQ(back.ranked[i].state, set.ranked[i].state);
    EXPECT_EQ(back.ranked[i].lineage_ranks, set.ranked[i].lineage_ranks);
  }
  const g::FurnitureGraph other = g::BuildFurnitureGraph({{0, 0}, 0}, {{"a", {2, 0}, {0.5, 0.5}, 0, pf}, {"b", {2, 1}, {0.5, 0.5}, 0, pf}}, 10, {});
  EXPECT_THROW(DecodeHypotheses(other, EncodeHypotheses(graph, set)), Error);
  std::string blob = EncodeHypotheses(graph, set);
  blob[blob.size() / 2] ^= 0x5a;
  EXPECT_THROW(DecodeHypotheses(graph, blob), Error);
}

}  // namespace
}  // namespace anchordb::services
