// Issue 16 acceptance 1 in the quick configuration, on PCL's test pair: verification accuracy of the shape models
// >= PCL's ISM. The furniture part (unseen views of the meshes, >= 70 %, beside PCL's ISM) is measured by
// anchordb_eval_shapes only: training PCL's ISM on the furniture scans takes many minutes, beyond a CI test.
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

}  // namespace
}  // namespace anchordb::eval
