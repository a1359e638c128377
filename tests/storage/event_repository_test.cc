// Instances, their label index (migration 0005, kept by triggers), history at a time, events with evidence, and the
// per-connection statement cache, on a real SQLite file.
#include "storage/event_repository.h"

#include <gtest/gtest.h>

#include "schema/error.h"

#include "storage/catalog.h"
#include "storage/dialect.h"
#include "storage/furniture_repository.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"
#include "tests/support/test_store.h"

namespace anchordb::storage {
namespace event_repository_test {

class EventRepositoryTest : public ::testing::TestWithParam<Engine> {
 protected:
  void SetUp() override { store_ = testing::OpenStoreWithMaps(db_.location(), {"home", "other"}); }
  using Labels = std::map<std::string, double>;
  static InstanceRecord Object(const std::string& map, const Labels& labels) {
    InstanceRecord r;
    r.map_id = map;
    r.labels = labels;
    r.created_ns = r.updated_ns = r.last_seen_ns = 10;
    return r;
  }
  std::vector<std::int64_t> WithLabel(const std::string& map, const std::string& label) {
    return store_->Read([&](Connection& c) {
      InstanceFilter f;
      f.label = label;
      std::vector<std::int64_t> ids;
      for (const auto& r : ListInstances(c, map, f, false)) ids.push_back(r.id);
      return ids;
    });
  }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Store> store_;
};

INSTANTIATE_TEST_SUITE_P(Engines, EventRepositoryTest, testing::BothEngines(), testing::EngineName);

TEST_P(EventRepositoryTest, LabelIndexFollowsEveryChangeOfTheLabels) {
  const auto [keys, cup, elsewhere] = store_->Write([](Connection& c) {
    return std::make_tuple(InsertInstance(c, Object("home", Labels{{"keys", 2.0}, {"wallet", 1.0}})),
                           InsertInstance(c, Object("home", Labels{{"cup", 1.0}})),
                           InsertInstance(c, Object("other", Labels{{"keys", 1.0}})));
  });
  EXPECT_EQ(WithLabel("home", "keys"), std::vector<std::int64_t>{keys});
  EXPECT_EQ(WithLabel("home", "wallet"), std::vector<std::int64_t>{keys});
  EXPECT_EQ(WithLabel("other", "keys"), std::vector<std::int64_t>{elsewhere});
  EXPECT_TRUE(WithLabel("home", "spoon").empty());
  store_->Write([&, cup_id = cup, keys_id = keys](Connection& c) {  // copies: clang 14 cannot capture a binding
    auto r = *FindInstance(c, "home", cup_id, false);
    r.labels = Labels{{"keys", 1.0}};  // relabelled: now also a candidate for the keys
    UpdateInstance(c, r);
    auto k = *FindInstance(c, "home", keys_id, false);
    k.labels = Labels{{"wallet", 1.0}};
    UpdateInstance(c, k);
  });
  EXPECT_EQ(WithLabel("home", "keys"), std::vector<std::int64_t>{cup});
  EXPECT_EQ(WithLabel("home", "wallet"), std::vector<std::int64_t>{keys});
  EXPECT_TRUE(WithLabel("home", "cup").empty());
  // The labels read back as written (and as updated), by id and in a listing; an instance without labels has none.
  const std::int64_t bare = store_->Write([](Connection& c) { return InsertInstance(c, Object("home", Labels{})); });
  store_->Read([&, cup_id = cup, keys_id = keys, other_id = elsewhere](Connection& c) {
    EXPECT_EQ(FindInstance(c, "home", cup_id, false)->labels, (Labels{{"keys", 1.0}}));
    EXPECT_EQ(FindInstance(c, "home", keys_id, true)->labels, (Labels{{"wallet", 1.0}}));
    EXPECT_EQ(FindInstance(c, "other", other_id, false)->labels, (Labels{{"keys", 1.0}}));
    EXPECT_TRUE(FindInstance(c, "home", bare, false)->labels.empty());
    std::map<std::int64_t, Labels> listed;
    for (const auto& r : ListInstances(c, "home", InstanceFilter{}, true)) {
      EXPECT_FALSE(listed.count(r.id)) << "instance " << r.id << " listed twice";
      listed[r.id] = r.labels;
    }
    EXPECT_EQ(listed, (std::map<std::int64_t, Labels>{{keys_id, {{"wallet", 1.0}}}, {cup_id, {{"keys", 1.0}}}, {bare, {}}}));
  });
  // Deleting an instance deletes its label rows.
  const auto label_rows = [&] {
    return store_->Read([](Connection& c) {
      Statement s(c, "SELECT COUNT(*) FROM instance_labels");
      s.Step();
      return s.Int(0);
    });
  };
  EXPECT_EQ(label_rows(), 3);
  store_->Write([&, cup_id = cup](Connection& c) {
    Statement s(c, "DELETE FROM instances WHERE id = ?");
    s.Bind(1, cup_id).Run();
  });
  EXPECT_EQ(label_rows(), 2);
}

TEST_P(EventRepositoryTest, InstanceVersionCountsEveryChangeOfTheMapsInstancesLabelsAndHistory) {
  const auto version = [&](const std::string& map) {
    return store_->Read([&](Connection& c) { return InstanceVersion(c, map); });
  };
  EXPECT_EQ(version("home"), 0);
  std::int64_t last = 0;
  const auto changed = [&](const char* what) {
    const std::int64_t now = version("home");
    EXPECT_GT(now, last) << what;
    last = now;
  };
  const std::int64_t id = store_->Write([](Connection& c) { return InsertInstance(c, Object("home", Labels{{"keys", 1.0}})); });
  changed("insert");
  store_->Write([&](Connection& c) {
    auto r = *FindInstance(c, "home", id, false);
    r.pinned = true;
    UpdateInstance(c, r);
  });
  changed("update");
  store_->Write([&](Connection& c) { AppendHistory(c, {id, 0, 100, true, {1, 2, 3}, std::nullopt}); });
  changed("history");
  store_->Write([&](Connection& c) {
    Statement s(c, "UPDATE instance_labels SET weight = 2 WHERE instance_id = ?");  // a label row alone
    s.Bind(1, id).Run();
  });
  changed("label");
  // Another map's writes and reads leave the count alone.
  const std::int64_t elsewhere = store_->Write([](Connection& c) { return InsertInstance(c, Object("other", Labels{})); });
  store_->Write([&](Connection& c) { AppendHistory(c, {elsewhere, 0, 100, true, {0, 0, 0}, std::nullopt}); });
  store_->Read([&](Connection& c) { ListInstances(c, "home", InstanceFilter{}, true); });
  EXPECT_EQ(version("home"), last);
  EXPECT_GT(version("other"), 0);
  store_->Write([&](Connection& c) {
    Statement s(c, "DELETE FROM instances WHERE id = ?");
    s.Bind(1, id).Run();
  });
  changed("delete");
  // Deleting the map takes its count with it; the count is derived, so a copy of the memory does not carry it.
  store_->Write([](Connection& c) { DeleteMap(c, "other"); });
  EXPECT_EQ(version("other"), 0);
  EXPECT_TRUE(IsDerivedTable("map_instance_versions"));
}

TEST_P(EventRepositoryTest, HistoryAtATimeAndEventsWithEvidence) {
  const std::int64_t id = store_->Write([](Connection& c) {
    const std::int64_t i = InsertInstance(c, Object("home", Labels{}));
    AppendHistory(c, {i, 0, 100, true, {1, 2, 3}, std::nullopt});
    AppendHistory(c, {i, 0, 200, false, {1, 2, 3}, std::nullopt});
    AppendHistory(c, {i, 0, 300, true, {4, 5, 6}, std::nullopt});
    return i;
  });
  store_->Read([&](Connection& c) {
    EXPECT_FALSE(HistoryAt(c, id, 99).has_value());
    EXPECT_TRUE(HistoryAt(c, id, 150)->present);
    EXPECT_FALSE(HistoryAt(c, id, 250)->present);
    EXPECT_EQ(HistoryAt(c, id, 1000)->position[0], 4.0);
    EXPECT_EQ(ListHistory(c, id).back().seq, 3);
  });
  // Events: evidence must name existing keyframes (a foreign key), so an event citing none is refused.
  EventRecord e;
  e.map_id = "home";
  e.type = "added";
  e.detection = "observed";
  e.instance_id = id;
  e.evidence = {{12345, "after"}};
  EXPECT_THROW(store_->Write([&](Connection& c) { InsertEvent(c, e); }), Error);
  e.evidence.clear();
  const std::int64_t event = store_->Write([&](Connection& c) { return InsertEvent(c, e); });
  // The same statement text run many times on one connection (the statement cache) gives fresh results each time.
  for (int k = 0; k < 50; ++k) {
    store_->Read([&](Connection& c) {
      EventFilter f;
      f.instance_id = id;
      const auto list = ListEvents(c, "home", f);
      ASSERT_EQ(list.size(), 1u);
      EXPECT_EQ(list[0].id, event);
      EXPECT_FALSE(FindEvent(c, "home", event + 1 + k).has_value());
    });
  }
}

TEST_P(EventRepositoryTest, WhereInputsInOneStatementAgreeWithTheSeparateQueries) {
  struct Ids {
    std::int64_t early, unplaced, table;
  };
  const Ids ids = store_->Write([](Connection& c) {
    const std::int64_t early = InsertInstance(c, Object("home", Labels{{"keys", 1.0}}));
    AppendHistory(c, {early, 0, 100, true, {1, 2, 3}, std::nullopt});
    AppendHistory(c, {early, 0, 300, true, {4, 5, 6}, std::nullopt});
    const std::int64_t unplaced = InsertInstance(c, Object("home", Labels{{"keys", 0.5}, {"cup", 0.5}}));  // no history
    InstanceRecord gone = Object("home", Labels{{"keys", 1.0}});
    gone.status = "deleted";
    InsertInstance(c, gone);
    InsertInstance(c, Object("home", Labels{{"wallet", 1.0}}));
    InsertInstance(c, Object("other", Labels{{"keys", 1.0}}));
    InstanceRecord table = Object("home", Labels{{"table", 0.75}, {"desk", 0.25}});
    table.kind = "furniture";
    table.position[0] = 7.5;
    table.extent[1] = 1.25;
    const std::int64_t table_id = InsertInstance(c, table);
    table.status = "deleted";
    InsertInstance(c, table);
    return Ids{early, unplaced, table_id};
  });
  const auto read_at = [&](std::int64_t at_ns) {
    return store_->ReadOneStatement([&](Connection& c) { return ReadWhereInputs(c, "home", "keys", at_ns); });
  };
  for (const std::int64_t at_ns : {50, 200, 1000}) {
    const WhereInputs in = read_at(at_ns);
    ASSERT_EQ(in.labelled.size(), 2u) << at_ns;  // not the deleted one, not the wallet, not the other map's
    EXPECT_EQ(in.labelled[0].instance.id, ids.early);
    EXPECT_EQ(in.labelled[1].instance.id, ids.unplaced);
    EXPECT_EQ(in.labelled[0].instance.labels, (Labels{{"keys", 1.0}}));
    EXPECT_EQ(in.labelled[1].instance.labels, (Labels{{"keys", 0.5}, {"cup", 0.5}}));  // every label, one instance
    EXPECT_FALSE(in.labelled[1].position.has_value());
    // The position at the time is HistoryAt's.
    const auto expected = store_->Read([&](Connection& c) { return HistoryAt(c, ids.early, at_ns); });
    ASSERT_EQ(in.labelled[0].position.has_value(), expected.has_value()) << at_ns;
    if (expected) {
      EXPECT_EQ(in.labelled[0].position->seq, expected->seq);
      EXPECT_EQ(in.labelled[0].position->stamp_ns, expected->stamp_ns);
      EXPECT_EQ(in.labelled[0].position->position[0], expected->position[0]);
    }
    ASSERT_EQ(in.furniture.size(), 1u);  // the deleted table is not furniture any more
    EXPECT_EQ(in.furniture[0].id, ids.table);
    EXPECT_EQ(in.furniture[0].kind, "furniture");
    EXPECT_EQ(in.furniture[0].position[0], 7.5);
    EXPECT_EQ(in.furniture[0].extent[1], 1.25);
    EXPECT_EQ(in.furniture[0].labels, (Labels{{"table", 0.75}, {"desk", 0.25}}));
    EXPECT_FALSE(in.stamp.newest_graph_id.has_value());
  }
  EXPECT_EQ(read_at(50).labelled[0].position, std::nullopt);
  EXPECT_EQ(read_at(1000).labelled[0].position->position[2], 6.0);
  // With furniture graphs the newest one's id, as NewestFurnitureGraphId says.
  store_->Write([](Connection& c) {
    for (int k = 0; k < 2; ++k) {
      FurnitureGraphRecord g;
      g.map_id = "home";
      g.knowledge_text = "{}";
      InsertFurnitureGraph(c, g);
    }
  });
  const auto newest = store_->Read([](Connection& c) { return NewestFurnitureGraphId(c, "home"); });
  ASSERT_TRUE(newest.has_value());
  EXPECT_EQ(read_at(1000).stamp.newest_graph_id, newest);
  // A map without anything: nothing, and no error (the service tells a missing map apart).
  const WhereInputs none = store_->ReadOneStatement([](Connection& c) { return ReadWhereInputs(c, "nowhere", "keys", 1); });
  EXPECT_TRUE(none.labelled.empty());
  EXPECT_TRUE(none.furniture.empty());
  EXPECT_FALSE(none.stamp.newest_graph_id.has_value());
}

}  // namespace
}  // namespace anchordb::storage
