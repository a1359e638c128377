// Prints the grounding evaluation (thesis 5.4.2 with synthetic participants) beside the thesis' figures.
//   anchordb_eval_grounding [--participants N] [--seed S] [--n N] [--sigma S] [--margin M] [--floor F] [--model joint] [--proximity_m X]
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "tests/eval/grounding_eval.h"

using namespace anchordb;

int main(int argc, char** argv) {
  int participants = 30;
  std::uint64_t seed = 1;
  eval::EvalOptions options;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--participants") == 0) participants = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--seed") == 0) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (std::strcmp(argv[i], "--n") == 0) options.n_best = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--sigma") == 0) options.sigma = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--margin") == 0) options.ambiguity_margin = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--floor") == 0) options.category_floor = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--proximity_m") == 0) options.joint.proximity_scale_m = std::atof(argv[i + 1]);
    else if (std::strcmp(argv[i], "--model") == 0) {
      options.model = std::strcmp(argv[i + 1], "joint") == 0 ? engine::grounding::Model::kJoint : engine::grounding::Model::kSequential;
    }
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const eval::Evaluation e = eval::Evaluate(participants, seed, options);
  std::printf("Grounding evaluation (thesis 5.4.2), synthetic participants: %d per speaker type (relative, prior, "
              "intrinsic), seeds %llu..%llu,\n6-8 pieces aligned with the view, 12-20 descriptions each, n = %d, sigma = %g\n\n",
              participants, static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed + participants - 1),
              options.n_best, options.sigma);
  std::printf("mean entropy of the visual p(f) over 10 categories [bits]: A %.3f  B %.3f  C %.3f   "
              "(thesis, unit and category count not stated: 1.815 / 1.867 / 2.199)\n\n",
              e.entropy_bits[0], e.entropy_bits[1], e.entropy_bits[2]);
  struct Thesis {
    const char* descriptions;
    const char* sequences;
    const char* mislabelled;
  };
  // Figure 5.18 / 5.20 as far as the text of 5.4.2 gives them.
  const Thesis thesis[3][3] = {
      {{"91.9 (all qualities)", "66.7", "< 3"}, {"66.7 (all qualities)", "40.0", "13.89"}, {"between", "almost 0", "-"}},
      {{"-", "-", "< 3"}, {"-", "-", "-"}, {"-", "-", "-"}},
      {{"-", "-", "24.44"}, {"-", "-", "38.22"}, {"-", "-", "-"}}};
  std::printf("%-3s %-14s | %12s %10s %13s %13s | %-22s %-9s %-11s\n", "q", "condition", "descriptions", "sequences",
              "mislabelled", "orientation", "thesis: descriptions %", "seq. %", "mislab. %");
  for (int q = 0; q < 3; ++q) {
    for (int c = 0; c < 3; ++c) {
      const eval::Tally t = e.Over(static_cast<eval::Quality>(q), static_cast<eval::Condition>(c));
      std::printf("%-3s %-14s | %10.1f %% %8.1f %% %11.1f %% %11.1f %% | %-22s %-9s %-11s\n",
                  eval::QualityName(static_cast<eval::Quality>(q)), eval::ConditionName(static_cast<eval::Condition>(c)),
                  100 * t.DescriptionRate(), 100 * t.SequenceRate(), 100 * (1 - t.VertexRate()), 100 * t.OrientationRate(),
                  thesis[q][c].descriptions, thesis[q][c].sequences, thesis[q][c].mislabelled);
    }
  }
  std::printf("(thesis: orientation right 17.78 %% averaged over all trials; few intrinsic descriptions were spoken)\n\n");
  std::printf("by speaker type, descriptions correct %% (sequences correct %%):\n");
  std::printf("%-3s %-10s | %-16s %-16s %-16s\n", "q", "speaker", "adaptation", "no adaptation", "uniform prior");
  for (int q = 0; q < 3; ++q) {
    for (int s = 0; s < 3; ++s) {
      std::printf("%-3s %-10s |", eval::QualityName(static_cast<eval::Quality>(q)), eval::SpeakerName(static_cast<eval::Speaker>(s)));
      for (int c = 0; c < 3; ++c) {
        const eval::Tally& t = e.tallies[q][c][s];
        std::printf(" %5.1f (%5.1f)    ", 100 * t.DescriptionRate(), 100 * t.SequenceRate());
      }
      std::printf("\n");
    }
  }
  std::printf("(thesis, all qualities: group R (relative) 47.9 %% without -> 80.7 %% with adaptation; group N 74.7 %% both)\n\n");
  for (int c = 0; c < 3; ++c) {
    const eval::Tally b = e.Over(eval::Quality::kB, static_cast<eval::Condition>(c));
    const eval::Tally cc = e.Over(eval::Quality::kC, static_cast<eval::Condition>(c));
    std::printf("misclassified piece corrected, %-14s: B %5.1f %% of %ld sequences, C %5.1f %% of %ld\n",
                eval::ConditionName(static_cast<eval::Condition>(c)), 100 * b.CorrectedRate(), b.misclassified,
                100 * cc.CorrectedRate(), cc.misclassified);
  }
  int worst = 0;
  for (int q = 0; q < 3; ++q) {
    for (int c = 0; c < 3; ++c) worst = std::max(worst, e.Over(static_cast<eval::Quality>(q), static_cast<eval::Condition>(c)).worst_rank_reverted);
  }
  for (int q = 0; q < 3; ++q) {
    const eval::Tally t = e.Over(static_cast<eval::Quality>(q), eval::Condition::kAdaptation);
    std::printf("quality %s, adaptation: %ld of %ld descriptions held as ambiguous (%ld of them wrongly matched at that "
                "moment); %ld wrongly matched and not held\n", eval::QualityName(static_cast<eval::Quality>(q)), t.held,
                t.descriptions, t.held_wrong, t.unheld_wrong);
  }
  std::printf("deepest reversion: the final best sequence passed through a hypothesis ranked %d (thesis: 60th-70th seen)\n", worst);
  return 0;
}
