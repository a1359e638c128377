#pragma once
// A simulated month of visits (issue 6, acceptance 3): three observations a day of two places (a table seen from
// two viewpoints, a shelf), each viewpoint jittered within the supersession thresholds; every third day the keys
// are carried from one place to the other (observed removal + observed addition); forgetting every night
// (keyframes after 3 days, events after 7, vacuum). Reports the database size per day and checks that every
// remaining event resolves its evidence and that "where are my keys?" still answers correctly.
#include <cstdint>
#include <string>
#include <vector>

namespace anchordb::testing {

struct MonthDay {
  int day = 0;
  std::int64_t file_bytes = 0;     // database + WAL after the night's forgetting and vacuum
  std::int64_t keyframes = 0;
  std::int64_t models_with_state = 0;
  std::int64_t events = 0;
  std::int64_t forgotten_keyframes = 0;  // deleted by that night's job
  bool where_right = false;        // the answer names the place the keys really are
};

struct MonthResult {
  std::vector<MonthDay> days;
  std::int64_t events_checked = 0;
  std::int64_t evidence_missing = 0;  // evidence keyframes of remaining events that do not resolve
  std::int64_t dry_run_changes = 0;   // rows changed by a dry run on the last night (must be 0)
};

MonthResult RunMonth(const std::string& db_path, int port, int days, bool verbose);

}  // namespace anchordb::testing
