// Prints the adversarial grounding evaluation of issue 17 as the table, the thesis model beside issue 17's.
//   anchordb_eval_grounding_adversarial [--rooms N] [--seed S]
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "tests/eval/grounding_adversarial.h"

using namespace anchordb::eval::adversarial;

int main(int argc, char** argv) {
  int rooms = 30;
  std::uint64_t seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--rooms") == 0) rooms = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--seed") == 0) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else return std::fprintf(stderr, "unknown option %s\n", argv[i]), 2;
  }
  const Table t = Evaluate(rooms, seed);
  std::printf("Adversarial grounding evaluation (issue 17): %d rooms per speaker type, seeds %llu..%llu\n", rooms,
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed + rooms - 1));
  std::printf("cells: graphs all right / descriptions right (worst room's share of right descriptions)\n\n");
  std::printf("%-10s | %-14s | %-34s | %-34s\n", "speakers", "model", "quality A", "quality B (one piece misclassified)");
  for (int s = 0; s < 3; ++s) {
    for (int m = 0; m < 2; ++m) {
      std::printf("%-10s | %-14s |", SpeakerName(static_cast<Speaker>(s)), ModelName(static_cast<Model>(m)));
      for (int q = 0; q < 2; ++q) {
        const Cell& c = t.cells[m][q][s];
        std::printf(" %4.2f / %4.2f (worst %4.2f)              |", c.GraphRate(), c.DescriptionRate(), c.worst_room_rate);
      }
      std::printf("\n");
    }
  }
  for (int m = 0; m < 2; ++m) {
    const Cell a = t.Over(static_cast<Model>(m), 0), b = t.Over(static_cast<Model>(m), 1);
    std::printf("all speakers, %-12s: A %4.2f / %4.3f (worst %4.2f), B %4.2f / %4.3f (worst %4.2f), descriptions overall %5.3f\n",
                ModelName(static_cast<Model>(m)), a.GraphRate(), a.DescriptionRate(), a.worst_room_rate, b.GraphRate(),
                b.DescriptionRate(), b.worst_room_rate, double(a.right + b.right) / double(a.descriptions + b.descriptions));
  }
  std::printf("(issue 17 bars: descriptions right >= 0.92 overall, A graphs 1.00, B graphs >= 0.85; thesis 91.9 %%)\n");
  return 0;
}
