// Issue 16 acceptance 1. On PCL's test pair in the quick configuration: verification accuracy of the shape models
// >= PCL's ISM. On the furniture meshes, ours only (the product's parameters, full configuration): unseen views of
// held-out seed 23 >= 70 % (about 85 s of CPU: training on 212 scans). The side-by-side furniture run with PCL's ISM
// is anchordb_eval_shapes only: training PCL's ISM on the furniture scans takes many minutes, beyond a CI test.
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

TEST(ShapeEvalTest, FurnitureUnseenViewsOfAHeldOutSeedAtLeast70Percent) {
  ASSERT_TRUE(FurnitureMeshesPresent()) << "shared data ../shared/data/aws_small_house/furniture_converted is absent";
  ShapeEvalConfig config = FullShapeEvalConfig();
  config.run_pcl = false;
  config.seed = 23;  // not used to choose the parameters (engine/shapes/README.md); measured 0.813
  const DatasetResult r = EvaluateFurnitureViews(config);
  std::cout << ResultTable(r);
  EXPECT_GE(r.ours.confusion.Total(), 100);
  EXPECT_GE(r.ours.confusion.Accuracy(), 0.70);
}

}  // namespace
}  // namespace anchordb::eval
