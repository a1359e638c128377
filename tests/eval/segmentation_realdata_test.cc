// Issue 16's segmentation bars on rooms furnished with the meshes of ../shared/data/aws_small_house (label realdata;
// the full configuration: anchordb_eval_segmentation).
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/eval/segmentation_eval.h"
#include "tests/support/real_data_files.h"

namespace anchordb::eval {
namespace {

TEST(SegmentationEvalRealData, MeshRoomsPrecisionAndRecall) {
  const auto s = EvaluateMeshRooms(2, 1, testing::SharedDataPath("aws_small_house/furniture_converted"));
  ASSERT_TRUE(s) << "the furniture meshes (../shared/data/aws_small_house/furniture_converted) are absent";
  std::printf("mesh rooms: precision %.3f recall %.3f category accuracy %.3f\n", s->precision(), s->recall(), s->category_accuracy());
  for (const auto& m : s->misses) std::printf("  %s\n", m.c_str());
  EXPECT_GE(s->precision(), 0.8);
  EXPECT_GE(s->recall(), 0.8);
}

}  // namespace
}  // namespace anchordb::eval
