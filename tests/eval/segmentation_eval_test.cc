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

}  // namespace
}  // namespace anchordb::eval
