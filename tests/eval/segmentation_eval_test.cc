// The bars of issue 16 on a small configuration (the full one: anchordb_eval_segmentation).
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/eval/segmentation_eval.h"

namespace anchordb::eval {
namespace {

TEST(SegmentationEval, BoxRoomsPrecisionAndRecall) {
  const SegmentationScore s = EvaluateBoxRooms(2, 1);
  std::printf("box rooms: precision %.3f recall %.3f category accuracy %.3f\n", s.precision(), s.recall(), s.category_accuracy());
  for (const auto& m : s.misses) std::printf("  %s\n", m.c_str());
  EXPECT_GE(s.precision(), 0.8);
  EXPECT_GE(s.recall(), 0.8);
}

TEST(SegmentationEval, LostKeyNamesTheDetectedTable) {
  const LostKeyScore s = EvaluateLostKey(1, 1);
  for (const auto& line : s.sentences) std::printf("  %s\n", line.c_str());
  EXPECT_EQ(s.named_table, s.runs);
}

// Acceptance 2 of issue 16 is 18 of 20 seeded runs (anchordb_eval_segmentation prints all 20); in these two of them
// flying pixels bridged the table to its neighbour into one segment (called sofa) before segmentation cut such
// bridges (with params.core_density = 0 both fail: "The keys are on the sofa.").
TEST(SegmentationEval, LostKeySeeds10To11NameTheDetectedTable) {
  const LostKeyScore s = EvaluateLostKey(2, 10);
  for (std::size_t i = 0; i < s.sentences.size(); ++i) std::printf("  seed %zu: %s [%s]\n", 10 + i, s.sentences[i].c_str(), s.segments[i].c_str());
  ASSERT_EQ(s.runs, 2);
  EXPECT_GE(s.named_table * 20, 18 * s.runs);  // 18 / 20 of the runs, here both
}

}  // namespace
}  // namespace anchordb::eval
