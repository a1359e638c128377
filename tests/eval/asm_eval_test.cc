// The thesis' single-viewpoint figures as a bar (3.5.1): A0 cleaned + transition zone F1 >= 0.97 in each of
// TA, SE, CA; the thin object of A2 is missed (low recall) because it does not rise above the noise threshold.
#include <gtest/gtest.h>

#include "tests/eval/asm_cases.h"

namespace anchordb::eval {
namespace {

class AsmA0Test : public ::testing::TestWithParam<sim::Setting> {};

TEST_P(AsmA0Test, CleanedWithTransitionZoneReachesTheThesis) {
  testing::PixelCounts zone, raw;
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    const AsmResult r = RunAsmCase(GetParam(), AsmCase::kA0, seed);
    ASSERT_GT(r.truth_pixels, 300u) << "the moved object must be well visible";
    zone += r.cleaned_zone;
    raw += r.raw;
  }
  RecordProperty("f1_cleaned_zone", std::to_string(zone.F1()));
  EXPECT_GE(zone.F1(), 0.97) << "P " << zone.Precision() << " R " << zone.Recall();
  // Cleaning and the zone can only help here; the raw layer is the weaker figure.
  EXPECT_GE(zone.F1(), raw.F1());
}

INSTANTIATE_TEST_SUITE_P(Settings, AsmA0Test, ::testing::Values(sim::Setting::kTA, sim::Setting::kSE, sim::Setting::kCA),
                         [](const ::testing::TestParamInfo<sim::Setting>& p) { return std::string(sim::SettingName(p.param)); });

TEST(AsmA2Test, ThinObjectIsMissedAsTheThesisExplains) {
  for (sim::Setting s : {sim::Setting::kTA, sim::Setting::kSE, sim::Setting::kCA}) {
    const AsmResult r = RunAsmCase(s, AsmCase::kA2, 1);
    ASSERT_GT(r.truth_pixels, 100u) << sim::SettingName(s);
    EXPECT_LT(r.cleaned_zone.Recall(), 0.3) << sim::SettingName(s);
    // ... while a regular object moved the same way in the same setting is found.
    EXPECT_GT(RunAsmCase(s, AsmCase::kA0, 1).cleaned_zone.Recall(), 0.9) << sim::SettingName(s);
  }
}

TEST(AsmA1Test, SlightMoveAlongTheMainAxisIsOnlyPartlyDetected) {
  const AsmResult r = RunAsmCase(sim::Setting::kTA, AsmCase::kA1, 1);
  EXPECT_LT(r.cleaned_zone.Recall(), 0.8);
  EXPECT_GT(r.cleaned_zone.Precision(), 0.5);
}

}  // namespace
}  // namespace anchordb::eval
