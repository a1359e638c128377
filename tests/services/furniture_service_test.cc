// FurnitureService without HTTP, on typed requests: a conversation grounded against a furniture graph, a restart in
// the middle that continues identically, bad input refused with the hypotheses unchanged, reset, speech
// production, the placement of a thing among the furniture, and the injected clock.
#include "services/furniture/furniture_service.h"

#include <gtest/gtest.h>

#include "api/furniture_json.h"  // to compare whole views as a client sees them
#include "schema/error.h"
#include "storage/repositories.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace furniture_service_test {

FurniturePieceRequest Piece(const std::string& id, double x, double y, double ex, double ey, std::vector<CategoryWeight> categories) {
  FurniturePieceRequest p;
  p.id = id;
  p.position_m = {x, y};
  p.extent_m = {ex, ey};
  p.categories = std::move(categories);
  return p;
}

// A living room seen from the door (map +x is the viewing direction, map +y the viewer's left).
CreateGraphRequest LivingRoom() {
  CreateGraphRequest r;
  r.furniture = {Piece("sofa", 4.0, 0.0, 0.9, 2.0, {{"armchair", 0.3}, {"sofa", 0.6}, {"table", 0.1}}),
                 Piece("plant", 4.0, 1.7, 0.4, 0.4, {{"plant", 0.7}, {"stool", 0.3}}),
                 Piece("table", 2.8, 0.0, 0.6, 1.0, {{"chair", 0.2}, {"stool", 0.2}, {"table", 0.6}}),
                 Piece("armchair", 2.8, -1.5, 0.8, 0.8, {{"armchair", 0.5}, {"chair", 0.2}, {"sofa", 0.3}}),
                 Piece("shelf", 4.2, -1.6, 0.4, 1.0, {{"armchair", 0.45}, {"shelf", 0.35}, {"wardrobe", 0.2}}),
                 Piece("stool", 2.8, 1.5, 0.4, 0.4, {{"chair", 0.2}, {"plant", 0.2}, {"stool", 0.6}})};
  r.params.n_best = 100;
  r.params.sigma = 3.0;
  return r;
}

DescriptionRequest Text(const std::string& text) { return {text, "", "", ""}; }
DescriptionRequest Words(const std::string& located, const std::string& relation, const std::string& reference) {
  return {std::nullopt, located, relation, reference};
}

const std::vector<DescriptionRequest>& Conversation() {
  static const std::vector<DescriptionRequest> kDescriptions = {
      Text("the plant is left of the sofa"),
      Words("table", "in_front_of", "sofa"),
      Text("behind the armchair is the shelf"),
      Text("the shelf is to the right of the couch"),
      Words("stool", "left of", "table"),
      Text("the armchair is right of the table"),
      Text("the sofa is behind the table"),
      Text("the table is to the right of the stool"),
  };
  return kDescriptions;
}

class FurnitureServiceTest : public ::testing::Test {
 protected:
  void Open() {
    storage::StoreOptions so;
    so.path = dir_.File("graphs.sqlite");
    store_ = std::make_unique<storage::Store>(so);
    service_ = std::make_unique<FurnitureService>(*store_, FurnitureSettings{}, clock_);
  }
  void Close() {
    service_.reset();
    store_.reset();
  }
  void SetUp() override {
    Open();
    store_->Write([](storage::Connection& c) { storage::InsertMap(c, {"home", "Home", 1}); });
  }
  // The graph as a client sees it, without the time stamps.
  static json::Json Stable(const GraphView& view) {
    json::Json j = api::ToJson(view);
    j.erase("created_ns");
    j.erase("updated_ns");
    return j;
  }

  FakeClock clock_{1'000'000'000};
  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<FurnitureService> service_;
};

TEST_F(FurnitureServiceTest, GroundsAConversationAndCorrectsTheMisclassifiedShelf) {
  const GraphView created = service_->Create("home", LivingRoom());
  EXPECT_EQ(created.descriptions, 0);
  EXPECT_FALSE(created.best.scheme);
  EXPECT_GE(created.edges.size(), 6u);
  EXPECT_EQ(created.created_ns, 1'000'000'000);
  EXPECT_NE(service_->knowledge_json().find("\"frame_prior\""), std::string::npos);  // the built-in tables
  clock_.AdvanceNs(5);
  for (const DescriptionRequest& d : Conversation()) service_->Describe("home", created.id, d);
  const GraphView g = service_->Get("home", created.id);
  EXPECT_EQ(g.updated_ns, 1'000'000'005);
  EXPECT_EQ(g.descriptions, 8);
  ASSERT_EQ(g.groundings.size(), 8u);
  const char* expected[8][2] = {{"plant", "sofa"}, {"table", "sofa"}, {"shelf", "armchair"}, {"shelf", "sofa"},
                                {"stool", "table"}, {"armchair", "table"}, {"sofa", "table"}, {"table", "stool"}};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(g.groundings[i].match.located, expected[i][0]) << i;
    EXPECT_EQ(g.groundings[i].match.reference, expected[i][1]) << i;
  }
  ASSERT_TRUE(g.groundings[0].understood && g.groundings[3].input);
  EXPECT_EQ(g.groundings[0].understood->located, "plant");
  EXPECT_EQ(g.groundings[3].input->text, "the shelf is to the right of the couch");
  // The shelf was seen as an armchair; the descriptions relabel it.
  for (const VertexView& v : g.vertices) EXPECT_EQ(v.label, v.id);
}

TEST_F(FurnitureServiceTest, RestartInTheMiddleContinuesIdentically) {
  // Uninterrupted.
  const std::int64_t a = service_->Create("home", LivingRoom()).id;
  for (const DescriptionRequest& d : Conversation()) service_->Describe("home", a, d);
  const json::Json final_a = Stable(service_->Get("home", a));
  const json::Json hyps_a = api::ToJson(service_->Hypotheses("home", a, 1000));
  // Interrupted after 3 descriptions: the service and the database are closed and reopened.
  const std::int64_t b = service_->Create("home", LivingRoom()).id;
  for (std::size_t i = 0; i < 3; ++i) service_->Describe("home", b, Conversation()[i]);
  Close();
  Open();
  for (std::size_t i = 3; i < Conversation().size(); ++i) service_->Describe("home", b, Conversation()[i]);
  json::Json final_b = Stable(service_->Get("home", b));
  json::Json hyps_b = api::ToJson(service_->Hypotheses("home", b, 1000));
  final_b["id"] = a;
  hyps_b["graph"] = a;
  EXPECT_EQ(final_a, final_b);
  // Hypothesis ids are per graph and therefore equal too.
  EXPECT_EQ(hyps_a, hyps_b);
  EXPECT_EQ(hyps_a["count"], 100);
}

void ExpectError(const std::function<void()>& f, ErrorCode code, const std::string& field, const std::string& word) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    return;
  }
  ADD_FAILURE() << "no error (expected one naming " << word << ")";
}

TEST_F(FurnitureServiceTest, BadInputIsRefusedAndLeavesTheHypothesesUnchanged) {
  const std::int64_t id = service_->Create("home", LivingRoom()).id;
  service_->Describe("home", id, Conversation()[0]);
  const json::Json before = api::ToJson(service_->Hypotheses("home", id, 1000));
  const json::Json graph_before = Stable(service_->Get("home", id));
  auto describe = [&](const DescriptionRequest& d) { return [this, id, d] { service_->Describe("home", id, d); }; };
  ExpectError(describe(Text("the bed is left of the sofa")), ErrorCode::kUnprocessable, "text", "'bed'");
  ExpectError(describe(Words("bed", "left_of", "sofa")), ErrorCode::kUnprocessable, "located", "'bed'");
  ExpectError(describe(Words("plant", "next_to", "sofa")), ErrorCode::kUnprocessable, "relation", "'next_to'");
  ExpectError(describe(Text("the plant is next to the sofa")), ErrorCode::kUnprocessable, "text", "'next to'");
  ExpectError(describe(Text("sofa plant left of")), ErrorCode::kUnprocessable, "text", "does not parse");
  EXPECT_EQ(api::ToJson(service_->Hypotheses("home", id, 1000)), before);
  EXPECT_EQ(Stable(service_->Get("home", id)), graph_before);
  // An empty graph, a graph without edges, unknown category words, repeated ids, parameters out of range.
  CreateGraphRequest empty = LivingRoom();
  empty.furniture.clear();
  ExpectError([&] { service_->Create("home", empty); }, ErrorCode::kUnprocessable, "furniture", "at least two");
  CreateGraphRequest apart = LivingRoom();
  apart.furniture.resize(2);
  apart.furniture[1].position_m = {40.0, 40.0};
  ExpectError([&] { service_->Create("home", apart); }, ErrorCode::kUnprocessable, "furniture", "no edges");
  CreateGraphRequest bed = LivingRoom();
  bed.furniture[2].categories = {{"bed", 1.0}};
  ExpectError([&] { service_->Create("home", bed); }, ErrorCode::kUnprocessable, "furniture[2].categories.bed", "'bed'");
  CreateGraphRequest zero = LivingRoom();
  zero.furniture[1].categories = {{"plant", 0.0}};
  ExpectError([&] { service_->Create("home", zero); }, ErrorCode::kUnprocessable, "furniture[1].categories", "all be zero");
  CreateGraphRequest twice = LivingRoom();
  twice.furniture[3].id = "sofa";
  ExpectError([&] { service_->Create("home", twice); }, ErrorCode::kConflict, "furniture[3].id", "'sofa'");
  CreateGraphRequest sigma = LivingRoom();
  sigma.params.sigma = 0.5;
  ExpectError([&] { service_->Create("home", sigma); }, ErrorCode::kUnprocessable, "params.sigma", "[1, 1000]");
  CreateGraphRequest n_best = LivingRoom();
  n_best.params.n_best = 2001;
  ExpectError([&] { service_->Create("home", n_best); }, ErrorCode::kUnprocessable, "params.n_best", "[1, 2000]");
  CreateGraphRequest many = LivingRoom();
  many.furniture.resize(65, many.furniture[0]);
  ExpectError([&] { service_->Create("home", many); }, ErrorCode::kPayloadTooLarge, "furniture", "at most 64");
  ExpectError([&] { service_->Create("nowhere", LivingRoom()); }, ErrorCode::kNotFound, "map", "nowhere");
  ExpectError([&] { service_->Get("home", 999); }, ErrorCode::kNotFound, "graph", "999");
  ExpectError([&] { service_->Get("nowhere", id); }, ErrorCode::kNotFound, "graph", "nowhere");
}

TEST_F(FurnitureServiceTest, ResetAndSpeechProduction) {
  const std::int64_t id = service_->Create("home", LivingRoom()).id;
  for (const DescriptionRequest& d : Conversation()) service_->Describe("home", id, d);
  // The listener names the shelf a shelf (it was seen as an armchair) and says "right of the sofa".
  const Utterance said = service_->Produce("home", id, {"shelf", "sofa"});
  EXPECT_EQ(said.located.label, "shelf");
  EXPECT_EQ(said.reference.label, "sofa");
  EXPECT_EQ(said.relation, engine::grounding::Relation::kRightOf);
  EXPECT_EQ(said.sentence, "the shelf is to the right of the sofa");
  ASSERT_EQ(said.alternatives.size(), 4u);
  EXPECT_EQ(said.alternatives[0].relation, said.relation);
  ExpectError([&] { service_->Produce("home", id, {"plant", "armchair"}); }, ErrorCode::kUnprocessable, "", "share no edge");
  ExpectError([&] { service_->Produce("home", id, {"ghost", "sofa"}); }, ErrorCode::kNotFound, "located", "ghost");
  ExpectError([&] { service_->Produce("home", id, {"sofa", "sofa"}); }, ErrorCode::kUnprocessable, "reference", "same vertex");
  const GraphView reset = service_->Reset("home", id);
  EXPECT_EQ(reset.descriptions, 0);
  EXPECT_EQ(reset.groundings.size(), 0u);
  EXPECT_EQ(service_->Hypotheses("home", id, 10).count, 1u);
  EXPECT_EQ(service_->Get("home", id).vertices[4].label, "armchair");  // as seen again
  const std::vector<GraphSummary> listed = service_->List("home", 0, 10);
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].params.n_best, 100);
}

TEST_F(FurnitureServiceTest, PlacesAThingAmongTheFurnitureOfTheNewestGraph) {
  EXPECT_FALSE(service_->Place("home", {3.0, 0.0, 0.8}));  // no graph yet
  const std::int64_t id = service_->Create("home", LivingRoom()).id;
  const std::optional<Placement> on = service_->Place("home", {2.8, 0.1, 0.8});
  ASSERT_TRUE(on);
  EXPECT_EQ(on->graph, id);
  EXPECT_EQ(on->furniture, "table");
  EXPECT_EQ(on->relation, "on");
  EXPECT_FALSE(on->frame);
  EXPECT_EQ(on->phrase, "on the table");
  const std::optional<Placement> beside = service_->Place("home", {2.8, 0.8, 0.0}, id);
  ASSERT_TRUE(beside);
  EXPECT_EQ(beside->furniture, "table");
  EXPECT_EQ(beside->relation, "left_of");
  EXPECT_EQ(beside->frame, "relative");
  EXPECT_EQ(beside->phrase, "to the left of the table");
  EXPECT_NEAR(beside->gap_m, 0.3, 1e-9);
}

}  // namespace
}  // namespace anchordb::services
