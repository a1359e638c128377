// Issue 15 acceptance 2: room categorisation on 60 synthetic rooms (10 per category), 5-fold CV, the thesis'
// E-SAMME set-up (maximum selection, z_f 0.6, eq. 4.10): test error after 20 rounds <= 0.25 (thesis KF-3D: 0.34),
// and FPFH alone better than SHOT alone, as in the thesis.
#include <gtest/gtest.h>

#include "tests/eval/rooms_eval.h"

namespace anchordb::eval {
namespace {

TEST(RoomsEvalTest, SixtyRoomsCrossValidatedBeatTheThesis) {
  RoomsEvalOptions o;
  o.esamme.rounds = 20;
  o.esamme.base = RoomsBaseSet();
  const RoomsData data = MakeRoomsData(o);
  ASSERT_EQ(data.bags.labels.size(), 60u);
  const auto folds = engine::StratifiedFolds(data.bags.labels, 5, o.seed);
  const auto all = engine::CrossValidate(data.bags, o.esamme, folds);
  EXPECT_LE(all.test_error_per_round[19], 0.25);
  double kinds = 0, types = 0;
  for (const auto& [k, v] : all.kind_share) kinds += v;
  for (const auto& [k, v] : all.feature_share) types += v;
  EXPECT_NEAR(kinds, 1.0, 1e-9);
  EXPECT_NEAR(types, 1.0, 1e-9);
  auto alone = [&](std::size_t t) {
    engine::TrainingSet one = data.bags;
    one.feature_types = {data.bags.feature_types[t]};
    one.features = {data.bags.features[t]};
    return engine::CrossValidate(one, o.esamme, folds).test_error_per_round[19];
  };
  EXPECT_LT(alone(0), alone(1));  // fpfh < shot
}

}  // namespace
}  // namespace anchordb::eval
