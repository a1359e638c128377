// Where-is answers for now reuse their stored inputs while the map's stamp is unchanged
// (services/events/where_inputs_cache.h): on both engines, a server answering from kept inputs still sees every change
// another server (another Store on the same database) writes: a move, a new piece of furniture, a relabel, the map
// deleted and made again. And the cache alone: bounded, keyed by stamp, 0 entries keeps nothing.
#include "services/events/where_inputs_cache.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "services/events/event_service.h"
#include "storage/event_repository.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/test_store.h"

namespace anchordb::services {
namespace where_inputs_cache_test {

storage::WhereInputs InputsAt(std::int64_t version, std::int64_t furniture = 0) {
  storage::WhereInputs in;
  in.stamp.map_created_ns = 7;
  in.stamp.instance_version = version;
  in.furniture.resize(static_cast<std::size_t>(furniture));
  return in;
}

TEST(WhereInputsCache, KeptInputsAreFoundOnlyAtTheirStamp) {
  WhereInputsCache cache(4);
  const storage::WhereInputs in = InputsAt(3, 2);
  EXPECT_FALSE(cache.Holds("a", "keys"));
  cache.Put("a", "keys", in);
  EXPECT_TRUE(cache.Holds("a", "keys"));
  EXPECT_FALSE(cache.Holds("a", "cup"));
  EXPECT_FALSE(cache.Holds("b", "keys"));
  ASSERT_TRUE(cache.Find("a", "keys", in.stamp));
  EXPECT_EQ(cache.Find("a", "keys", in.stamp)->furniture.size(), 2u);
  EXPECT_EQ(cache.hits(), 2);
  storage::WhereStamp later = in.stamp;
  later.instance_version = 4;
  EXPECT_FALSE(cache.Find("a", "keys", later));
  storage::WhereStamp other_graph = in.stamp;
  other_graph.newest_graph_id = 1;
  EXPECT_FALSE(cache.Find("a", "keys", other_graph));
  storage::WhereStamp made_again = in.stamp;
  made_again.map_created_ns = 8;
  EXPECT_FALSE(cache.Find("a", "keys", made_again));
  EXPECT_EQ(cache.hits(), 2);
  cache.Put("a", "keys", InputsAt(4, 5));  // replaces
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_FALSE(cache.Find("a", "keys", in.stamp));
  EXPECT_EQ(cache.Find("a", "keys", later)->furniture.size(), 5u);
}

TEST(WhereInputsCache, TheOldestEntryGoesWhenFullAndZeroEntriesKeepNothing) {
  WhereInputsCache cache(2);
  cache.Put("a", "keys", InputsAt(1));
  cache.Put("a", "cup", InputsAt(1));
  cache.Put("a", "keys", InputsAt(2));  // a replacement is no new entry
  cache.Put("b", "keys", InputsAt(1));
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_FALSE(cache.Holds("a", "keys"));
  EXPECT_TRUE(cache.Holds("a", "cup"));
  EXPECT_TRUE(cache.Holds("b", "keys"));

  WhereInputsCache none(0);
  none.Put("a", "keys", InputsAt(1));
  EXPECT_FALSE(none.Holds("a", "keys"));
  WhereInputsCache some(2);
  storage::WhereInputs no_map = InputsAt(1);
  no_map.stamp.map_created_ns.reset();
  some.Put("gone", "keys", no_map);
  EXPECT_FALSE(some.Holds("gone", "keys"));
}

// Two servers on one database: `a` answers, `b` writes.
class WhereCacheAcrossServersTest : public ::testing::TestWithParam<storage::Engine> {
 protected:
  void SetUp() override {
    store_a_ = testing::OpenStoreWithMaps(db_.location(), {"home"});
    store_b_ = testing::OpenStoreWithMaps(db_.location(), {});
    a_ = std::make_unique<EventService>(*store_a_, nullptr, EventSettings{});
    b_ = std::make_unique<EventService>(*store_b_, nullptr, EventSettings{});
  }
  std::int64_t Create(InstanceKind kind, const std::string& label, Eigen::Vector3d p, Eigen::Vector3d extent, std::int64_t stamp_ns) {
    CreateInstanceRequest r;
    r.kind = kind;
    r.label = label;
    r.position_m = p;
    r.extent_m = extent;
    r.stamp_ns = stamp_ns;
    return b_->CreateInstance("home", r).id;
  }
  WhereAnswer WhereNow(const std::string& label) { return a_->Where("home", WhereRequest{label, std::nullopt}); }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<storage::Store> store_a_, store_b_;
  std::unique_ptr<EventService> a_, b_;
};
INSTANTIATE_TEST_SUITE_P(Engines, WhereCacheAcrossServersTest, testing::BothEngines(), testing::EngineName);

TEST_P(WhereCacheAcrossServersTest, AnAnswerFromKeptInputsSeesEveryChangeAnotherServerWrote) {
  const std::int64_t t0 = 1'000'000'000'000LL;
  Create(InstanceKind::kFurniture, "table", {1.0, 1.0, 0.4}, {0.8, 1.2, 0.75}, t0);
  const std::int64_t keys = Create(InstanceKind::kObject, "keys", {1.1, 1.2, 0.8}, {0.05, 0.05, 0.02}, t0);

  WhereAnswer first = WhereNow("keys");
  EXPECT_EQ(first.instance_id, keys);
  EXPECT_NEAR(first.position_m.x(), 1.1, 1e-9);
  ASSERT_TRUE(first.placement);
  EXPECT_EQ(first.placement->name, "table");
  const std::int64_t hits = a_->where_cache().hits();
  WhereAnswer again = WhereNow("keys");
  EXPECT_EQ(a_->where_cache().hits(), hits + 1) << "an unchanged map is answered from the kept inputs";
  EXPECT_EQ(again.sentence, first.sentence);

  // Moved by the other server: a new history entry.
  store_b_->Write([&](storage::Connection& c) {
    storage::HistoryRecord h;
    h.instance_id = keys;
    h.stamp_ns = t0 + 1'000'000'000;
    h.position[0] = 4.0;
    h.position[1] = 4.2;
    h.position[2] = 0.9;
    storage::AppendHistory(c, h);
  });
  WhereAnswer moved = WhereNow("keys");
  EXPECT_EQ(a_->where_cache().hits(), hits + 1) << "a changed stamp is a miss";
  EXPECT_NEAR(moved.position_m.x(), 4.0, 1e-9);
  EXPECT_NEAR(moved.position_m.z(), 0.9, 1e-9);

  // A shelf the keys now lie on.
  Create(InstanceKind::kFurniture, "shelf", {4.0, 4.2, 0.45}, {1.0, 0.4, 0.9}, t0);
  WhereAnswer on_shelf = WhereNow("keys");
  ASSERT_TRUE(on_shelf.placement);
  EXPECT_EQ(on_shelf.placement->name, "shelf");
  EXPECT_NE(on_shelf.sentence, first.sentence);

  // The past is never kept: at= reads the time asked.
  WhereAnswer before = a_->Where("home", WhereRequest{"keys", t0 + 1});
  EXPECT_NEAR(before.position_m.x(), 1.1, 1e-9);

  // An operator says they are a wallet: nothing is labelled keys any more.
  b_->LabelInstance("home", keys, LabelRequest{"wallet", LabelSource::kOperator});
  try {
    WhereNow("keys");
    ADD_FAILURE() << "the relabelled object was still answered for 'keys'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
  EXPECT_EQ(WhereNow("wallet").instance_id, keys);

  // The map deleted and made again under the same id, by the other server.
  store_b_->Write([&](storage::Connection& c) {
    ASSERT_TRUE(storage::DeleteMap(c, "home"));
    storage::InsertMap(c, {"home", "home", 2});
  });
  const std::int64_t new_wallet = Create(InstanceKind::kObject, "wallet", {5.0, 5.5, 0.8}, {0.1, 0.1, 0.02}, t0);
  WhereAnswer fresh = WhereNow("wallet");
  EXPECT_EQ(fresh.instance_id, new_wallet);
  EXPECT_NEAR(fresh.position_m.y(), 5.5, 1e-9);
  EXPECT_FALSE(fresh.placement) << "the new map has no furniture";
}

}  // namespace
}  // namespace anchordb::services
