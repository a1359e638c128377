// Issue 6 acceptance 3: a simulated month with forgetting every night keeps the database size bounded while every
// event resolves its evidence, where-is answers right every day, and a dry run changes nothing.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/eval/month_eval.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

namespace anchordb::testing {
namespace {

TEST(MonthEvalTest, NightlyForgettingKeepsTheDatabaseBoundedAndEveryReferenceResolvable) {
  TempDir dir;
  const std::string db = dir.File("month.sqlite");
  ServerProcess server(db);
  const MonthResult r = RunMonth(db, server.port(), 30, false);
  ASSERT_EQ(r.days.size(), 30u);
  // The retention windows (keyframes 3 days, events 7) are full after the first week: from then on the size stays
  // within 20 % of the second week's largest.
  std::int64_t second_week = 0, rest = 0;
  for (const MonthDay& d : r.days) {
    if (d.day >= 8 && d.day <= 14) second_week = std::max(second_week, d.file_bytes);
    if (d.day > 14) rest = std::max(rest, d.file_bytes);
    EXPECT_TRUE(d.where_right) << "day " << d.day;
    EXPECT_LE(d.models_with_state, 3) << "day " << d.day << ": superseded models keep their state";
  }
  EXPECT_GT(second_week, 0);
  EXPECT_LE(rest, second_week * 12 / 10) << "second week max " << second_week << " bytes, later max " << rest;
  // Something was forgotten every few nights (the month is not bounded by doing nothing).
  std::int64_t forgotten = 0;
  for (const MonthDay& d : r.days) forgotten += d.forgotten_keyframes;
  EXPECT_GT(forgotten, 50);
  EXPECT_GT(r.events_checked, 0);
  EXPECT_EQ(r.evidence_missing, 0);
  EXPECT_EQ(r.dry_run_changes, 0);
}

}  // namespace
}  // namespace anchordb::testing
