// Issue 16 acceptance 1 in the quick configuration: verification accuracy of the shape models >= PCL's ISM on
// PCL's test pair and on unseen views of the furniture meshes, and >= 70 % over the furniture categories.
#include <gtest/gtest.h>

#include <iostream>

#include "tests/eval/shape_eval.h"

namespace anchordb::eval {
namespace {

TEST(ShapeEvalTest, PclTestPairAtLeastPclIsm) {
  ASSERT_TRUE(PclTestPairPresent()) << "shared data ../shared/data/pcl_test (ism_*.pcd, bun0/bun4.pcd) is absent";
  const DatasetResult r = EvaluatePclTestPair(QuickShapeEvalConfig());
  std::cout << ResultTable(r);
  EXPECT_GE(r.ours.confusion.Accuracy(), r.pcl.confusion.Accuracy());
  EXPECT_GE(r.ours.confusion.Accuracy(), 0.75);
}

TEST(ShapeEvalTest, FurnitureUnseenViewsAtLeastSeventyPercentAndPclIsm) {
  ASSERT_TRUE(FurnitureMeshesPresent()) << "shared data ../shared/data/aws_small_house/furniture_converted is absent";
  const DatasetResult r = EvaluateFurnitureViews(QuickShapeEvalConfig());
  std::cout << ResultTable(r);
  EXPECT_GE(r.ours.confusion.Accuracy(), 0.70);
  EXPECT_GE(r.ours.confusion.Accuracy(), r.pcl.confusion.Accuracy());
}

}  // namespace
}  // namespace anchordb::eval
