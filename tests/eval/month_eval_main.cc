// Prints a simulated month with nightly forgetting (issue 6, acceptance 3): database size and contents per day.
//   anchordb_eval_month [--days N] [--verbose]   (ANCHORDB_BIN: the server binary)
#include <cstdio>
#include <cstring>

#include "tests/eval/month_eval.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

int main(int argc, char** argv) {
  int days = 30;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--days") && i + 1 < argc) days = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else {
      std::fprintf(stderr, "usage: anchordb_eval_month [--days N] [--verbose]\n");
      return 2;
    }
  }
  anchordb::testing::TempDir dir;
  const std::string db = dir.File("month.sqlite");
  anchordb::testing::ServerProcess server(db);
  const auto r = anchordb::testing::RunMonth(db, server.port(), days, verbose);
  std::printf("day  database [MB]  keyframes  models with state  events  keyframes forgotten  where-is\n");
  for (const auto& d : r.days) {
    std::printf("%3d  %13.2f  %9lld  %17lld  %6lld  %19lld  %s\n", d.day, d.file_bytes / 1e6, static_cast<long long>(d.keyframes),
                static_cast<long long>(d.models_with_state), static_cast<long long>(d.events),
                static_cast<long long>(d.forgotten_keyframes), d.where_right ? "right" : "WRONG");
  }
  std::printf("events checked %lld, evidence keyframes missing %lld, rows changed by a dry run %lld\n",
              static_cast<long long>(r.events_checked), static_cast<long long>(r.evidence_missing),
              static_cast<long long>(r.dry_run_changes));
  return 0;
}
