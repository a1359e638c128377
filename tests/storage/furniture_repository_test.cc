// Furniture-graph rows and their descriptions: write, close, reopen, compare; optimistic versioning; cascades.
#include "storage/furniture_repository.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace {

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
    r.viewpoint_json = R"({"position":[0,0],"heading_rad":0})";
    r.params_json = R"({"n_best":100})";
    r.knowledge_json = "{}";
    r.graph_json = R"({"vertices":[]})";
    r.created_ns = r.updated_ns = 42;
    r.hypotheses = "initial";
    id = store.Write([&](Connection& c) { return InsertFurnitureGraph(c, r); });
    store.Write([&](Connection& c) {
      InsertGraphDescription(c, {id, 1, R"({"text":"the plant is left of the sofa"})", "plant", "left_of", "sofa", 43});
      UpdateFurnitureGraphState(c, id, 1, blob, 44, 0);
    });
    // A writer that read version 0 is refused now.
    EXPECT_THROW(store.Write([&](Connection& c) { UpdateFurnitureGraphState(c, id, 1, "stale", 45, 0); }), Error);
    EXPECT_THROW(store.Write([&](Connection& c) {
                   InsertGraphDescription(c, {id, 1, "{}", "a", "left_of", "b", 46});
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
  EXPECT_EQ(r->graph_json, R"({"vertices":[]})");
  EXPECT_FALSE(store.Read([&](Connection& c) { return FindFurnitureGraph(c, "elsewhere", id, false); }).has_value());
  const auto d = store.Read([&](Connection& c) { return ListGraphDescriptions(c, id); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].relation, "left_of");
  EXPECT_EQ(store.Read([&](Connection& c) { return ListFurnitureGraphs(c, "home", 0, 10); }).size(), 1u);
  store.Write([&](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_TRUE(store.Read([&](Connection& c) { return ListGraphDescriptions(c, id); }).empty());
}

}  // namespace
}  // namespace anchordb::storage
