// Prints the event-detection evaluation (thesis 3.5.2) beside the thesis' figures: the lost-key scenario repeated
// with seeded variation against a real server started on loopback.
//   anchordb_eval_events [--seeds N] [--first_seed N] [--verbose]   (ANCHORDB_BIN: the server binary)
#include <cstdio>
#include <cstring>
#include <string>

#include "tests/eval/events_eval.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

using namespace anchordb;

int main(int argc, char** argv) {
  int seeds = 20;
  std::uint64_t first = 1;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) seeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--first_seed") && i + 1 < argc) first = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else {
      std::fprintf(stderr, "usage: anchordb_eval_events [--seeds N] [--first_seed N] [--verbose]\n");
      return 2;
    }
  }
  testing::TempDir dir;
  testing::ServerProcess server(dir.File("events.sqlite"));
  const testing::EventsSummary s = testing::RunEventsEvaluation(server.port(), first, seeds, verbose);
  std::printf("seed  observed tp/fp/fn  meanwhile tp/fp/fn  events right  where right  past right  answer\n");
  int right = 0, where_right_when_right = 0;
  for (const auto& r : s.runs) {
    std::printf("%4llu  %8d/%d/%d  %9d/%d/%d  %12s  %11s  %10s  %s\n", static_cast<unsigned long long>(r.seed),
                r.score.observed.tp, r.score.observed.fp, r.score.observed.fn, r.score.meanwhile.tp, r.score.meanwhile.fp,
                r.score.meanwhile.fn, r.events_right ? "yes" : "no", r.where_right ? "yes" : "no", r.past_right ? "yes" : "no",
                r.sentence.c_str());
    right += r.events_right;
    where_right_when_right += r.events_right && r.where_right;
  }
  const auto total = s.total.Total();
  std::printf("\n                      anchordb   thesis (3.5.2, 17 runs)\n");
  std::printf("recall                %.3f      0.923\n", testing::EventsSummary::Recall(total));
  std::printf("precision             %.3f      0.882\n", testing::EventsSummary::Precision(total));
  std::printf("error rate observed   %.3f      0.049\n", testing::EventsSummary::ErrorRate(s.total.observed));
  std::printf("error rate meanwhile  %.3f      0.235\n", testing::EventsSummary::ErrorRate(s.total.meanwhile));
  std::printf("runs with every event right: %d of %zu; of those, where-is right: %d\n", right, s.runs.size(), where_right_when_right);
  return 0;
}
