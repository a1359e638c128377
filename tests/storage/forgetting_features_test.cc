// Forgetting and anchored features (migration 0012): the features of a deleted keyframe go with it (and their R*Tree
// rows), exact repeats are removed, and the report counts both.
#include "storage/feature_repository.h"
#include "tests/storage/forgetting_fixture.h"

namespace anchordb::storage::forget_test {
namespace forgetting_features_test {

using forgetting_features = ForgetFixture;

INSTANTIATE_TEST_SUITE_P(Engines, forgetting_features, testing::BothEngines(), testing::EngineName);

TEST_P(forgetting_features, FeaturesOfDeletedKeyframesAndExactRepeatsGo) {
  const std::int64_t scene = Scene("closed", kNow - 50 * kDay, std::nullopt);
  const std::int64_t old_kf = Keyframe(scene, kNow - 40 * kDay);
  const std::int64_t recent_kf = Keyframe(scene, kNow - kDay);
  const auto feature = [&](std::optional<std::int64_t> kf, float v, double x) {
    return store_->Write([&](Connection& c) {
      FeatureRecord f;
      f.map = "home";
      f.type = "x_test";
      f.descriptor = {v, 1.0f};
      f.anchor_m = Eigen::Vector3d(x, 0, 0);
      f.keyframe = kf;
      return InsertFeature(c, f);
    });
  };
  feature(old_kf, 1, 0);
  feature(old_kf, 2, 1);
  const std::int64_t kept = feature(recent_kf, 3, 2);
  const std::int64_t first = feature(std::nullopt, 4, 3);
  feature(std::nullopt, 4, 3);  // an exact repeat of `first`
  ForgetPolicy policy;
  policy.keyframe_max_age_s = 30.0 * 86400;
  const ForgetReport r = Run(policy, false);
  EXPECT_EQ(r.keyframes_deleted, (std::vector<std::int64_t>{old_kf}));
  EXPECT_EQ(r.features_deleted, 2);
  EXPECT_EQ(r.features_deduplicated, 1);
  store_->Read([&](Connection& c) {
    FeatureFilter all;
    std::vector<std::int64_t> ids;
    for (const auto& f : ListFeatures(c, "home", all)) ids.push_back(f.id);
    EXPECT_EQ(ids, (std::vector<std::int64_t>{kept, first}));
    if (c.engine() == Engine::kSqlite) {  // the R*-tree table kept in step (PostgreSQL indexes the rows themselves)
      EXPECT_EQ(Count(c, "SELECT COUNT(*) FROM feature_anchors"), 2);
    }
    EXPECT_EQ(ForeignKeyCheck(c), "");
  });
}

}  // namespace
}  // namespace anchordb::storage::forget_test
