// A change event's details on both engines (migration 0020): every part round-trips through the typed columns and
// event_label_weights, absent parts stay absent (an empty distribution is not an absent one), the weights go with
// their event, and the JSON documents of schema 19 read back through the typed columns.
#include <gtest/gtest.h>

#include "storage/connection.h"
#include "storage/event_repository.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace event_details_test {

class EventDetailsTest : public ::testing::TestWithParam<Engine> {
 protected:
  void Open(int up_to_version) {
    c_ = OpenConnection(db_.location(), ConnectionOptions{});
    std::vector<Migration> migrations;
    for (const Migration& m : EmbeddedMigrations(GetParam())) {
      if (up_to_version == 0 || m.version <= up_to_version) migrations.push_back(m);
    }
    ApplyMigrations(*c_, migrations);
    InsertMap(*c_, {"home", "Home", 1});
  }
  std::int64_t Insert(const EventDetailsRecord& details, const std::string& type = "moved") {
    EventRecord e;
    e.map_id = "home";
    e.type = type;
    e.detection = "observed";
    e.stamp_ns = e.created_ns = 100;
    e.details = details;
    return InsertEvent(*c_, e);
  }
  EventDetailsRecord Read(std::int64_t id) { return FindEvent(*c_, "home", id).value().details; }
  std::int64_t Count(const std::string& table) {
    Statement s(*c_, "SELECT count(*) FROM " + table);
    s.Step();
    return s.Int(0);
  }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Connection> c_;
};
INSTANTIATE_TEST_SUITE_P(Engines, EventDetailsTest, testing::BothEngines(), testing::EngineName);

TEST_P(EventDetailsTest, EveryPartRoundTripsAndAbsentPartsStayAbsent) {
  Open(0);
  EventDetailsRecord full;
  full.segment = EventSegmentDetails{{1.25, -0.5, 0.75}, {0.2, 0.1, 0.3}, 812};
  full.move = EventMoveDetails{{2.0, 3.5, 0.7}, 0.875, 41};
  full.visibility = EventVisibilityDetails{3, 120, 40, 7, 2};
  full.background_scene = 9;
  full.label_weights = std::map<std::string, double>{{"cup", 0.75}, {"mug", 0.25}};
  const EventDetailsRecord back = Read(Insert(full));
  ASSERT_TRUE(back.segment && back.move && back.visibility && back.background_scene && back.label_weights);
  EXPECT_EQ(back.segment->centroid_m, full.segment->centroid_m);
  EXPECT_EQ(back.segment->extent_m, full.segment->extent_m);
  EXPECT_EQ(back.segment->points, 812);
  EXPECT_EQ(back.move->from_m, full.move->from_m);
  EXPECT_EQ(back.move->size_similarity, 0.875);
  EXPECT_EQ(back.move->removal_event, 41);
  EXPECT_EQ(back.visibility->confirmed, 120);
  EXPECT_EQ(back.visibility->seen_through, 40);
  EXPECT_EQ(back.visibility->unmeasured, 2);
  EXPECT_EQ(*back.background_scene, 9);
  EXPECT_EQ(*back.label_weights, *full.label_weights);

  EventDetailsRecord move_without_removal;
  move_without_removal.move = EventMoveDetails{{0.0, 0.0, 0.0}, 0.5, std::nullopt};
  const EventDetailsRecord m = Read(Insert(move_without_removal));
  ASSERT_TRUE(m.move.has_value());
  EXPECT_FALSE(m.move->removal_event.has_value());
  EXPECT_FALSE(m.segment || m.visibility || m.background_scene || m.label_weights);

  EventDetailsRecord empty_distribution;
  empty_distribution.label_weights.emplace();
  const EventDetailsRecord e = Read(Insert(empty_distribution, "labelled"));
  ASSERT_TRUE(e.label_weights.has_value());
  EXPECT_TRUE(e.label_weights->empty());
  EXPECT_FALSE(Read(Insert({})).label_weights.has_value());

  EventFilter f;
  const std::vector<EventRecord> listed = ListEvents(*c_, "home", f);
  ASSERT_EQ(listed.size(), 4u);
  EXPECT_EQ(listed[0].details.label_weights->at("cup"), 0.75);
  EXPECT_TRUE(DeleteEvent(*c_, "home", listed[0].id));
  EXPECT_EQ(Count("event_label_weights"), 0);
}

TEST_P(EventDetailsTest, DocumentsOfSchema19BecomeTypedColumns) {
  Open(19);
  const auto legacy = [&](const std::string& type, const std::string& details) {
    Statement s(*c_, "INSERT INTO events (map_id, type, detection, stamp_ns, details, created_ns) "
                     "VALUES ('home', ?, 'observed', 5, ?, 5) RETURNING id");
    s.Bind(1, type).Bind(2, details);
    return s.RunReturningId();
  };
  const std::int64_t moved = legacy("moved", R"({"segment":{"centroid_m":[1.5,-2.25,0.5],"extent_m":[0.25,0.125,0.5],)"
                                             R"("points":300},"from_m":[4.0,1.0,0.75],"size_similarity":0.9,"removal_event":7})");
  const std::int64_t removed = legacy("removed", R"({"visibility":{"confirmed":10,"seen_through":20,"hidden":3,)"
                                                 R"("unmeasured":4,"outside":5},"background_scene":12})");
  const std::int64_t labelled = legacy("labelled", R"({"labels":{"keys":1.0,"wallet":0.5}})");
  const std::int64_t plain = legacy("added", "{}");
  const std::int64_t unresolved = legacy("moved", R"({"from_m":[1,2,3],"removal_event":null})");
  std::vector<Migration> all = EmbeddedMigrations(GetParam());
  ApplyMigrations(*c_, all);

  const EventDetailsRecord a = Read(moved);
  ASSERT_TRUE(a.segment && a.move);
  EXPECT_EQ(a.segment->centroid_m, (std::array<double, 3>{1.5, -2.25, 0.5}));
  EXPECT_EQ(a.segment->points, 300);
  EXPECT_EQ(a.move->from_m, (std::array<double, 3>{4.0, 1.0, 0.75}));
  EXPECT_EQ(a.move->size_similarity, 0.9);
  EXPECT_EQ(a.move->removal_event, 7);
  EXPECT_FALSE(a.visibility || a.background_scene || a.label_weights);
  const EventDetailsRecord b = Read(removed);
  ASSERT_TRUE(b.visibility.has_value());
  EXPECT_EQ(b.visibility->hidden, 3);
  EXPECT_EQ(b.visibility->outside, 5);
  EXPECT_EQ(b.background_scene, 12);
  const EventDetailsRecord l = Read(labelled);
  ASSERT_TRUE(l.label_weights.has_value());
  EXPECT_EQ(*l.label_weights, (std::map<std::string, double>{{"keys", 1.0}, {"wallet", 0.5}}));
  const EventDetailsRecord p = Read(plain);
  EXPECT_FALSE(p.segment || p.move || p.visibility || p.background_scene || p.label_weights);
  const EventDetailsRecord u = Read(unresolved);
  ASSERT_TRUE(u.move.has_value());
  EXPECT_FALSE(u.move->removal_event.has_value());
  EXPECT_EQ(u.move->size_similarity, 0.0);
}

}  // namespace
}  // namespace anchordb::storage
