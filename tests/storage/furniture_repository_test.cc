// Furniture-graph rows and their descriptions: write, close, reopen, compare; optimistic versioning; cascades; the
// JSON documents of schema 22 read back through the typed columns and child tables of migration 0023.
#include "storage/furniture_repository.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace furniture_repository_test {

class FurnitureRepositoryTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, FurnitureRepositoryTest, testing::BothEngines(), testing::EngineName);

TEST_P(FurnitureRepositoryTest, RoundTripAcrossReopenWithVersioningAndCascade) {
  StoreOptions so;
  so.path = db_.location();
  std::int64_t id = 0;
  const std::string blob("\x01\x00\x02hypotheses", 13);
  {
    Store store(so);
    store.Write([](Connection& c) { InsertMap(c, {"home", "Home", 1}); });
    FurnitureGraphRecord r;
    r.map_id = "home";
    r.viewpoint_position_m = {1.5, -2.0};
    r.viewpoint_heading_rad = 0.75;
    r.params.grounding_model = "joint";
    r.params.n_best = 100;
    r.params.adaptation = true;
    r.params.orientation_prior = "room";
    r.params.occupancy_layer = "floor";
    r.knowledge_text = "{}";
    r.category_count = 3;
    r.vertices = {{"12", {2.0, 1.0}, {0.8, 0.4}, 0.5, {0.5, 0.3, 0.2}, {0.25, 0.25, 0.4, 0.1}},
                  {"13", {3.0, 1.0}, {0.6, 0.6}, 0.0, {0.1, 0.1, 0.8}, {0.7, 0.1, 0.1, 0.1}}};
    r.edges = {{0, 1, 0.2, {{{0.1, 0.2, 0.3, 0.4}, {0.4, 0.3, 0.2, 0.1}}}}};
    r.created_ns = r.updated_ns = 42;
    r.hypotheses = "initial";
    id = store.Write([&](Connection& c) { return InsertFurnitureGraph(c, r); });
    store.Write([&](Connection& c) {
      GraphDescriptionRecord said{id, 1, "the plant is left of the sofa", "", "", "", "plant", "left_of", "sofa", 43};
      InsertGraphDescription(c, said);
      GraphDescriptionRecord named{id, 2, std::nullopt, "chair", "right_of", "table", "chair", "right_of", "table", 44};
      InsertGraphDescription(c, named);
      UpdateFurnitureGraphState(c, id, 1, blob, 44, 0);
    });
    // A writer that read version 0 is refused now.
    EXPECT_THROW(store.Write([&](Connection& c) { UpdateFurnitureGraphState(c, id, 1, "stale", 45, 0); }), Error);
    EXPECT_THROW(store.Write([&](Connection& c) {
                   InsertGraphDescription(c, {id, 1, "again", "", "", "", "a", "left_of", "b", 46});
                 }),
                 Error);
  }
  Store store(so);
  const auto r = store.Read([&](Connection& c) { return FindFurnitureGraph(c, "home", id, true); });
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->hypotheses, blob);
  EXPECT_EQ(r->state_version, 1);
  EXPECT_EQ(r->descriptions, 1);
  EXPECT_EQ(r->updated_ns, 44);
  EXPECT_EQ(r->viewpoint_position_m, (std::array<double, 2>{1.5, -2.0}));
  EXPECT_EQ(r->viewpoint_heading_rad, 0.75);
  EXPECT_EQ(r->params.grounding_model, "joint");
  EXPECT_EQ(r->params.n_best, 100);
  EXPECT_TRUE(r->params.adaptation);
  EXPECT_EQ(r->params.orientation_prior, "room");
  EXPECT_EQ(r->params.occupancy_layer, "floor");
  EXPECT_EQ(r->category_count, 3);
  ASSERT_EQ(r->vertices.size(), 2u);
  EXPECT_EQ(r->vertices[1].id, "13");
  EXPECT_EQ(r->vertices[0].extent_m, (std::array<double, 2>{0.8, 0.4}));
  EXPECT_EQ(r->vertices[0].categories, (std::vector<double>{0.5, 0.3, 0.2}));
  EXPECT_EQ(r->vertices[1].orientations, (std::array<double, 4>{0.7, 0.1, 0.1, 0.1}));
  ASSERT_EQ(r->edges.size(), 1u);
  EXPECT_EQ(r->edges[0].b, 1);
  EXPECT_EQ(r->edges[0].visual[1], (std::array<double, 4>{0.4, 0.3, 0.2, 0.1}));
  EXPECT_FALSE(store.Read([&](Connection& c) { return FindFurnitureGraph(c, "elsewhere", id, false); }).has_value());
  const auto d = store.Read([&](Connection& c) { return ListGraphDescriptions(c, id); });
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].input_text, std::optional<std::string>("the plant is left of the sofa"));
  EXPECT_EQ(d[0].relation, "left_of");
  EXPECT_FALSE(d[1].input_text.has_value());
  EXPECT_EQ(d[1].input_located, "chair");
  EXPECT_EQ(d[1].input_reference, "table");
  const auto listed = store.Read([&](Connection& c) { return ListFurnitureGraphs(c, "home", 0, 10); });
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].params.n_best, 100);
  EXPECT_TRUE(listed[0].vertices.empty());  // a listing reads no graph structure
  store.Write([&](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_TRUE(store.Read([&](Connection& c) { return ListGraphDescriptions(c, id); }).empty());
  for (const char* table : {"furniture_graph_vertices", "furniture_graph_vertex_categories", "furniture_graph_edges"}) {
    EXPECT_EQ(store.Read([&](Connection& c) {
                Statement rows(c, std::string("SELECT count(*) FROM ") + table);
                rows.Step();
                return rows.Int(0);
              }),
              0)
        << table;
  }
}

TEST_P(FurnitureRepositoryTest, TheDocumentsOfSchema22BecomeTypedColumnsAndChildRows) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  std::vector<Migration> up_to_22;
  for (const Migration& m : EmbeddedMigrations(GetParam())) {
    if (m.version <= 22) up_to_22.push_back(m);
  }
  ApplyMigrations(*c, up_to_22);
  InsertMap(*c, {"home", "Home", 1});
  const auto legacy = [&](const std::string& params, const std::string& graph) {
    Statement s(*c, "INSERT INTO furniture_graphs (map_id, viewpoint, params, knowledge, graph, created_ns, updated_ns, "
                    "hypotheses) VALUES ('home', ?, ?, '{}', ?, 1, 1, ?) RETURNING id");
    s.Bind(1, std::string_view(R"({"position":[0.5,-1.25],"heading_rad":1.5})")).Bind(2, params).Bind(3, graph);
    s.BindBlob(4, "h");
    return s.RunReturningId();
  };
  const std::string graph = R"({"category_count":2,"vertices":[
      {"id":"7","position":[1,2],"extent":[0.5,0.25],"yaw_rad":0.1,"categories":[0.75,0.25],"orientations":[0.1,0.2,0.3,0.4]},
      {"id":"8","position":[2,2],"extent":[0.5,0.5],"yaw_rad":0,"categories":[0.5,0.5]}],
    "edges":[{"a":0,"b":1,"gap_m":0.3,"visual":[[0.1,0.2,0.3,0.4],[0.5,0.2,0.2,0.1]]}]})";
  const std::int64_t now = legacy(R"({"model":"joint","n_best":50,"sigma":2.5,"edge_max_gap_m":1.5,"relation_sharpness":3,
      "adaptation":true,"frame_prior":"uniform","ambiguity_margin":0.5,"category_floor":0.1,"orientation_prior":"room",
      "occupancy_layer":"occ"})", graph);
  const std::int64_t before = legacy(R"({"n_best":100,"sigma":3,"edge_max_gap_m":1.5,"relation_sharpness":3,
      "adaptation":false,"frame_prior":"statistical"})", graph);
  Statement(*c, "INSERT INTO furniture_graph_descriptions (graph_id, seq, input, located, relation, reference, created_ns) "
                "VALUES (?, 1, '{\"text\":\"the cup left of the plate\"}', 'cup', 'left_of', 'plate', 2), "
                "(?, 2, '{\"located\":\"cup\",\"relation\":\"right_of\",\"reference\":\"plate\"}', 'cup', "
                "'right_of', 'plate', 3)")
      .Bind(1, now).Bind(2, now).Run();
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const FurnitureGraphRecord a = *FindFurnitureGraph(*c, "home", now, false);
  EXPECT_EQ(a.viewpoint_position_m, (std::array<double, 2>{0.5, -1.25}));
  EXPECT_EQ(a.viewpoint_heading_rad, 1.5);
  EXPECT_EQ(a.params.grounding_model, "joint");
  EXPECT_EQ(a.params.n_best, 50);
  EXPECT_TRUE(a.params.adaptation);
  EXPECT_EQ(a.params.frame_prior, "uniform");
  EXPECT_EQ(a.params.ambiguity_margin, 0.5);
  EXPECT_EQ(a.params.orientation_prior, "room");
  EXPECT_EQ(a.params.occupancy_layer, "occ");
  EXPECT_EQ(a.category_count, 2);
  ASSERT_EQ(a.vertices.size(), 2u);
  EXPECT_EQ(a.vertices[0].id, "7");
  EXPECT_EQ(a.vertices[0].extent_m, (std::array<double, 2>{0.5, 0.25}));
  EXPECT_EQ(a.vertices[0].categories, (std::vector<double>{0.75, 0.25}));
  EXPECT_EQ(a.vertices[0].orientations, (std::array<double, 4>{0.1, 0.2, 0.3, 0.4}));
  EXPECT_EQ(a.vertices[1].orientations, (std::array<double, 4>{0.25, 0.25, 0.25, 0.25}));  // before issue 17: uniform
  ASSERT_EQ(a.edges.size(), 1u);
  EXPECT_EQ(a.edges[0].gap_m, 0.3);
  EXPECT_EQ(a.edges[0].visual[1], (std::array<double, 4>{0.5, 0.2, 0.2, 0.1}));
  // A graph of an older release: the defaults the server applied.
  const FurnitureGraphRecord b = *FindFurnitureGraph(*c, "home", before, false);
  EXPECT_EQ(b.params.grounding_model, "sequential");
  EXPECT_FALSE(b.params.adaptation);
  EXPECT_EQ(b.params.frame_prior, "statistical");
  EXPECT_EQ(b.params.ambiguity_margin, 0.0);
  EXPECT_EQ(b.params.orientation_prior, "uniform");
  EXPECT_EQ(b.params.occupancy_layer, "");
  const std::vector<GraphDescriptionRecord> d = ListGraphDescriptions(*c, now);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].input_text, std::optional<std::string>("the cup left of the plate"));
  EXPECT_FALSE(d[1].input_text.has_value());
  EXPECT_EQ(d[1].input_relation, "right_of");
  EXPECT_EQ(d[1].relation, "right_of");
}

}  // namespace
}  // namespace anchordb::storage
