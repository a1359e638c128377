// Prints the single-viewpoint ASM evaluation (cases A0-A4 in settings TA, SE, CA) beside the thesis' figures.
//   anchordb_eval_asm [--seeds N]
#include <cstdio>
#include <cstring>
#include <string>

#include "tests/eval/asm_cases.h"

using namespace anchordb;

int main(int argc, char** argv) {
  int seeds = 3;
  for (int i = 1; i + 1 < argc; ++i) if (std::strcmp(argv[i], "--seeds") == 0) seeds = std::atoi(argv[i + 1]);
  struct Thesis {
    eval::AsmCase c;
    const char* figure;
  };
  const Thesis cases[] = {{eval::AsmCase::kA0, "raw F1 0.808 (P 0.735, R 0.896); cleaned+zone F1 0.973"},
                          {eval::AsmCase::kA1, "F1 0.576"},
                          {eval::AsmCase::kA2, "F1 0.092"},
                          {eval::AsmCase::kA3, "F1 0.917 (TA only)"},
                          {eval::AsmCase::kA4, "no figure (objects not separated)"}};
  const sim::Setting settings[] = {sim::Setting::kTA, sim::Setting::kSE, sim::Setting::kCA};
  std::printf("ASM single-viewpoint evaluation, %d seeds per case and setting, 10 + 10 frames, beta 0.03\n", seeds);
  std::printf("%-4s %-3s %7s | %-26s | %-26s | %-34s\n", "case", "set", "truth", "raw F1 / P / R", "cleaned F1 / P / R",
              "cleaned+zone F1 / P / R / FPR");
  for (const Thesis& t : cases) {
    testing::PixelCounts all_raw, all_clean, all_zone;
    for (sim::Setting s : settings) {
      if (t.c == eval::AsmCase::kA3 && s != sim::Setting::kTA) continue;
      testing::PixelCounts raw, clean, zone;
      std::size_t truth = 0;
      for (int seed = 1; seed <= seeds; ++seed) {
        const eval::AsmResult r = eval::RunAsmCase(s, t.c, static_cast<std::uint64_t>(seed));
        raw += r.raw, clean += r.cleaned, zone += r.cleaned_zone, truth += r.truth_pixels;
      }
      all_raw += raw, all_clean += clean, all_zone += zone;
      std::printf("%-4s %-3s %7zu | %.3f / %.3f / %.3f      | %.3f / %.3f / %.3f      | %.3f / %.3f / %.3f / %.4f\n",
                  eval::AsmCaseName(t.c), sim::SettingName(s), truth / seeds, raw.F1(), raw.Precision(), raw.Recall(),
                  clean.F1(), clean.Precision(), clean.Recall(), zone.F1(), zone.Precision(), zone.Recall(), zone.Fpr());
    }
    std::printf("%-4s all          | %.3f / %.3f / %.3f      | %.3f / %.3f / %.3f      | %.3f / %.3f / %.3f / %.4f   thesis: %s\n",
                eval::AsmCaseName(t.c), all_raw.F1(), all_raw.Precision(), all_raw.Recall(), all_clean.F1(),
                all_clean.Precision(), all_clean.Recall(), all_zone.F1(), all_zone.Precision(), all_zone.Recall(),
                all_zone.Fpr(), t.figure);
  }
  return 0;
}
