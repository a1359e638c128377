// Server presence (storage/server_presence.h) on both engines: a server's own id and another running server's id
// are running; once the other's session ends its id is not; text no server was given names nobody. SQLite: one
// server has the file, so no other id is running.
#include "storage/server_presence.h"

#include <gtest/gtest.h>

#include "tests/support/pg_scratch.h"
#include "tests/support/test_store.h"

namespace anchordb::storage {
namespace server_presence_test {

class ServerPresenceTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, ServerPresenceTest, testing::BothEngines(), testing::EngineName);

TEST_P(ServerPresenceTest, AnotherServerRunsWhileItsSessionLastsAndTwoServersGetTwoIds) {
  const auto store = testing::OpenStoreWithMaps(db_.location(), {});  // migrated
  ServerPresence a(db_.location(), {}, 42);
  EXPECT_EQ(a.id().size(), 8u);
  EXPECT_TRUE(a.Running(a.id()));
  EXPECT_TRUE(a.Hold());
  EXPECT_TRUE(a.Hold()) << "holding again does not fail";
  EXPECT_FALSE(a.Running("not an id"));
  EXPECT_FALSE(a.Running(""));
  auto b = std::make_unique<ServerPresence>(db_.location(), ConnectionOptions{}, 42);  // the same seed
  const std::string b_id = b->id();
  if (GetParam() == Engine::kPostgresql) {
    EXPECT_NE(b_id, a.id()) << "a running server's id is not given twice";
    EXPECT_TRUE(a.Running(b_id));
    EXPECT_TRUE(b->Running(a.id()));
    EXPECT_TRUE(a.Running(b_id)) << "asking does not take the other's lock away";
  } else {
    EXPECT_FALSE(a.Running("0000002b")) << "an id of the right form, but SQLite has one server";
  }
  b.reset();  // its session ends
  EXPECT_FALSE(a.Running(b_id == a.id() ? "ffffffff" : b_id));
  ServerPresence c(db_.location(), {}, 7);
  EXPECT_TRUE(c.Running(c.id()));
  if (GetParam() == Engine::kPostgresql) EXPECT_TRUE(c.Running(a.id()));
  else EXPECT_FALSE(c.Running(a.id())) << "SQLite: one server has the file";
}

}  // namespace
}  // namespace anchordb::storage
