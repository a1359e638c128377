// The audit service on a real SQLite file: an entry begun for a request is inserted in the change's own write
// transaction (committed with it, rolled back with it), completed with the outcome afterwards, and inserted whole
// when no write carried it; listing filters and pages.
#include "services/audit/audit_service.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/repositories.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace audit_service_test {

class AuditServiceTest : public ::testing::Test {
 protected:
  storage::StoreOptions Options() {
    storage::StoreOptions o;
    o.path = dir_.File("db.sqlite");
    return o;
  }
  std::vector<AuditEntry> All() { return audit_.List({}).entries; }
  void InsertToken(const std::string& id) {
    store_.Write([&](storage::Connection& c) { storage::InsertToken(c, {id, "h" + id, "reader", 1}); });
  }
  static AuditEntry Entry(const std::string& action) {
    AuditEntry e;
    e.actor = "tok_1", e.role = "admin", e.action = action, e.map = "home", e.before_json = R"({"pinned":false})";
    return e;
  }

  testing::TempDir dir_;
  storage::Store store_{Options()};
  FakeClock clock_{1'000};
  AuditService audit_{store_, clock_};
};

TEST_F(AuditServiceTest, EntryCommitsWithTheChangeThenGetsItsOutcome) {
  auto in_flight = audit_.Begin(Entry("instance.pin"));
  InsertToken("t1");
  // Committed with the change, before the answer is known (as a crash now would leave it): status 0, no after.
  const auto pending = All();
  ASSERT_EQ(pending.size(), 1u);
  EXPECT_EQ(pending[0].status, 0);
  EXPECT_FALSE(pending[0].after_json);
  InsertToken("t2");  // a second write of the same request carries nothing
  clock_.AdvanceNs(5);
  const AuditEntry done = audit_.Finish(in_flight, 200, R"({"pinned":true})");
  const auto all = All();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].id, done.id);
  EXPECT_EQ(all[0].status, 200);
  EXPECT_EQ(all[0].time_ns, 1'000);  // when the request began
  EXPECT_EQ(*all[0].before_json, R"({"pinned":false})");
  EXPECT_EQ(*all[0].after_json, R"({"pinned":true})");
}

TEST_F(AuditServiceTest, EntryRollsBackWithAFailedChangeAndIsRecordedWithTheError) {
  auto in_flight = audit_.Begin(Entry("instance.delete"));
  EXPECT_THROW(store_.Write([](storage::Connection& c) {
                 storage::InsertToken(c, {"t1", "h", "reader", 1});
                 throw Error(ErrorCode::kConflict, "refused");
               }),
               Error);
  EXPECT_TRUE(All().empty());
  EXPECT_EQ(store_.Read([](storage::Connection& c) { return storage::CountTokens(c); }), 0);
  audit_.Finish(in_flight, 409, std::nullopt);
  const auto all = All();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].status, 409);
  EXPECT_EQ(all[0].action, "instance.delete");
}

TEST_F(AuditServiceTest, RequestWithoutWritesIsInsertedWhole) {
  auto in_flight = audit_.Begin(Entry("GET /v1/maps/{map}"));
  audit_.Finish(in_flight, 200, std::nullopt);
  InsertToken("t1");  // disarmed: a later write of the thread carries no entry
  const auto all = All();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].status, 200);
}

TEST_F(AuditServiceTest, ListFiltersAndPages) {
  for (const char* action : {"instance.pin", "instance.unpin", "map.delete"}) {
    clock_.AdvanceNs(100);
    audit_.Record(Entry(action));
  }
  AuditQuery q;
  q.action = "instance.unpin";
  ASSERT_EQ(audit_.List(q).entries.size(), 1u);
  q = {};
  q.since_ns = 1'200;
  EXPECT_EQ(audit_.List(q).entries.size(), 2u);
  q.until_ns = 1'300;
  EXPECT_EQ(audit_.List(q).entries.size(), 1u);
  q = {};
  q.limit = 2;
  const AuditPage first = audit_.List(q);
  ASSERT_TRUE(first.next_after);
  q.after_id = *first.next_after;
  const AuditPage rest = audit_.List(q);
  EXPECT_EQ(rest.entries.size(), 1u);
  EXPECT_FALSE(rest.next_after);
  q.limit = 0;
  EXPECT_THROW(audit_.List(q), Error);
}

}  // namespace
}  // namespace anchordb::services
