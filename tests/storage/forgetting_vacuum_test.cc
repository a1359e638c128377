// Vacuum after forgetting (storage/forgetting.h): SQLite's incremental vacuum on a real file, PostgreSQL's VACUUM on
// a scratch server.
// Suite names are lower case so that `ctest -R forget` selects them.
#include "storage/forgetting.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "tests/storage/forgetting_fixture.h"

namespace anchordb::storage {
namespace forgetting_vacuum_test {

using namespace forget_test;  // NOLINT: the fixture and its helpers are this file's vocabulary

// Incremental vacuum: the first vacuum switches a file in auto_vacuum=NONE mode to INCREMENTAL (VACUUM), later ones
// run PRAGMA incremental_vacuum; both shrink the file on disk.
class forgetting_vacuum : public ForgetFixture {};
INSTANTIATE_TEST_SUITE_P(Engines, forgetting_vacuum, ::testing::Values(Engine::kSqlite), testing::EngineName);

TEST_P(forgetting_vacuum, ShrinksTheFile) {
  const std::int64_t closed = Scene("closed", kNow - 20 * kDay, std::nullopt);
  const auto fill = [&](int n) {
    for (int i = 0; i < n; ++i) Keyframe(closed, kNow - 10 * kDay, false, 0.0, 20000);
    Keyframe(closed, kNow - 1 * kDay, false, 0.0, 20000);  // a recent one stays
  };
  fill(150);
  ForgetPolicy p;
  p.vacuum = true;
  const ForgetReport first = Run(p, false);
  EXPECT_EQ(first.keyframes_deleted.size(), 150u);
  EXPECT_EQ(first.vacuum_mode, "switched_to_incremental");
  EXPECT_GT(first.file_bytes_before, 150 * 40000);
  EXPECT_LT(first.file_bytes_after, first.file_bytes_before / 10);
  EXPECT_EQ(first.freelist_after_vacuum, 0);
  const std::int64_t size_first = DatabaseFileBytes(store_->path());
  EXPECT_EQ(size_first, first.file_bytes_after);
  store_->Write([](Connection& c) { EXPECT_EQ(Count(c, "PRAGMA auto_vacuum"), 2); });

  fill(100);
  const std::int64_t grown = DatabaseFileBytes(store_->path());
  const ForgetReport second = Run(p, false);
  EXPECT_EQ(second.keyframes_deleted.size(), 100u);
  EXPECT_EQ(second.vacuum_mode, "incremental");
  EXPECT_GT(grown, 100 * 40000);
  EXPECT_LT(second.file_bytes_after, grown / 5);
  EXPECT_EQ(second.freelist_after_vacuum, 0);
  std::printf("[ figures ] vacuum (switch): %lld -> %lld bytes; incremental: %lld -> %lld bytes\n",
              static_cast<long long>(first.file_bytes_before), static_cast<long long>(first.file_bytes_after),
              static_cast<long long>(second.file_bytes_before), static_cast<long long>(second.file_bytes_after));
  EXPECT_EQ(store_->IntegrityCheck(), "ok");
  store_->Write([](Connection& c) { EXPECT_EQ(ForeignKeyCheck(c), ""); });
  // A dry run with vacuum does not vacuum.
  EXPECT_EQ(Run(p, true).vacuum_mode, "skipped (dry run)");
}

// PostgreSQL: forgetting with vacuum runs VACUUM on the tables it deleted from (after its transaction: VACUUM cannot
// run inside one) and reports the database's size before and after; a dry run does not vacuum.
class forgetting_vacuum_server : public ForgetFixture {};
INSTANTIATE_TEST_SUITE_P(Engines, forgetting_vacuum_server, ::testing::Values(Engine::kPostgresql),
                         testing::EngineName);

TEST_P(forgetting_vacuum_server, VacuumsTheTablesItDeletedFrom) {
  const std::int64_t closed = Scene("closed", kNow - 20 * kDay, std::nullopt);
  for (int i = 0; i < 40; ++i) Keyframe(closed, kNow - 10 * kDay, false, 0.0, 20000);
  Keyframe(closed, kNow - 1 * kDay, false, 0.0, 20000);
  ForgetPolicy p;
  p.vacuum = true;
  EXPECT_EQ(Run(p, true).vacuum_mode, "skipped (dry run)");
  const ForgetReport r = Run(p, false);
  EXPECT_EQ(r.keyframes_deleted.size(), 40u);
  EXPECT_EQ(r.vacuum_mode, "postgresql_vacuum");
  EXPECT_GT(r.file_bytes_before, 0);
  EXPECT_GT(r.file_bytes_after, 0);
  EXPECT_GT(r.page_count_after_vacuum, 0);
  const std::int64_t left = store_->Read([](Connection& c) { return Count(c, "SELECT count(*) FROM keyframes"); });
  EXPECT_EQ(left, 1);
}

}  // namespace
}  // namespace anchordb::storage
