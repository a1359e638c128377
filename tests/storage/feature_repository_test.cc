// Anchored features (migration 0012) on a real SQLite file: R*Tree box and radius queries, time filters, the anchor
// index kept in step when a keyframe or a map cascades its features away, codebooks and classifiers across a reopen.
#include "storage/classifier_documents.h"
#include "storage/feature_repository.h"

#include <gtest/gtest.h>

#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace feature_repository_test {

class FeatureRepositoryTest : public ::testing::TestWithParam<Engine> {
 protected:
  void SetUp() override { Open(); }
  void Open() {
    store_.reset();
    StoreOptions o;
    o.path = db_.location();
    o.reader_connections = 1;
    store_ = std::make_unique<Store>(o);
  }
  static FeatureRecord Feature(const std::string& type, Eigen::Vector3d at, std::int64_t stamp,
                               std::optional<std::int64_t> keyframe = std::nullopt) {
    FeatureRecord f;
    f.map = "home";
    f.type = type;
    f.descriptor = {1.0f, 2.0f, static_cast<float>(stamp)};
    f.anchor_m = at;
    f.stamp_ns = stamp;
    f.keyframe = keyframe;
    return f;
  }
  std::int64_t AnchorRows() {
    return store_->Read([](Connection& c) {
      // SQLite: rows of the R*-tree table (kept by triggers); PostgreSQL: rows found through the GiST point index.
      Statement s(c, c.engine() == Engine::kSqlite
                         ? "SELECT COUNT(*) FROM feature_anchors"
                         : "SELECT COUNT(*) FROM features WHERE point(x_m, y_m) <@ box(point(1e300, 1e300), "
                           "point(-1e300, -1e300))");
      s.Step();
      return s.Int(0);
    });
  }
  std::int64_t Keyframe() {
    return store_->Write([](Connection& c) {
      SceneRecord scene;
      scene.map_id = "home";
      KeyframeRecord k;
      k.map_id = "home";
      k.scene_id = InsertScene(c, scene);
      k.kind = "begin";
      k.depth = k.background = "x";
      return InsertKeyframe(c, k);
    });
  }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Store> store_;
};

INSTANTIATE_TEST_SUITE_P(Engines, FeatureRepositoryTest, testing::BothEngines(), testing::EngineName);

TEST_P(FeatureRepositoryTest, SpatialAndTimeQueriesAndCascades) {
  store_->Write([](Connection& c) { InsertMap(c, {"home", "home", 1}); });
  const std::int64_t kf = Keyframe();
  store_->Write([&](Connection& c) {
    InsertFeature(c, Feature("fpfh", {0, 0, 0}, 10));
    InsertFeature(c, Feature("fpfh", {1, 0, 0}, 20, kf));
    InsertFeature(c, Feature("fpfh", {3, 3, 1}, 30, kf));
    InsertFeature(c, Feature("shot", {0.1, 0, 0}, 40));
  });
  EXPECT_EQ(AnchorRows(), 4);
  auto list = [&](const FeatureFilter& q) {
    return store_->Read([&](Connection& c) {
      std::vector<float> stamps;
      for (const auto& f : ListFeatures(c, "home", q)) stamps.push_back(f.descriptor.at(2));
      return stamps;
    });
  };
  FeatureFilter radius;
  radius.near_m = Eigen::Vector3d(0, 0, 0);
  radius.radius_m = 1.01;
  EXPECT_EQ(list(radius), (std::vector<float>{10, 20, 40}));
  radius.type = "fpfh";
  radius.radius_m = 0.99;
  EXPECT_EQ(list(radius), (std::vector<float>{10}));
  FeatureFilter box;
  box.box_min_m = Eigen::Vector3d(0.5, -1, -1);
  box.box_max_m = Eigen::Vector3d(4, 4, 2);
  EXPECT_EQ(list(box), (std::vector<float>{20, 30}));
  FeatureFilter time;
  time.since_ns = 20;
  time.until_ns = 40;
  EXPECT_EQ(list(time), (std::vector<float>{20, 30}));
  FeatureFilter of_keyframe;
  of_keyframe.keyframe = kf;
  EXPECT_EQ(list(of_keyframe).size(), 2u);
  EXPECT_EQ(store_->Read([](Connection& c) { return StoredFeatureDims(c, "home", "shot"); }), 3);
  EXPECT_EQ(store_->Read([](Connection& c) { return StoredFeatureDims(c, "home", "spd"); }), std::nullopt);

  // Forgetting a keyframe drops its features, and the R*Tree rows go with them.
  store_->Write([&](Connection& c) { Statement(c, "DELETE FROM keyframes WHERE id = ?").Bind(1, kf).Run(); });
  EXPECT_EQ(list(FeatureFilter{}), (std::vector<float>{10, 40}));
  EXPECT_EQ(AnchorRows(), 2);
  store_->Write([](Connection& c) { DeleteMap(c, "home"); });
  EXPECT_EQ(AnchorRows(), 0);
}

TEST_P(FeatureRepositoryTest, CodebooksAndClassifiersSurviveAReopen) {
  store_->Write([](Connection& c) {
    InsertMap(c, {"home", "home", 1});
    CodebookRecord b;
    b.map = "home";
    b.type = "fpfh";
    b.words = 2;
    b.dims = 3;
    b.seed = 7;
    b.centres = {1, 2, 3, 4, 5, 6};
    b.features = 10;
    UpsertCodebook(c, b);
    ClassifierRecord k;
    k.name = "rooms";
    k.created_ns = 5;
    k.model = std::string("ESAM\0\x01", 6);
    ClassifierOptionsRecord options;
    options.name = "rooms";
    options.base = {{"svm", 1.0, 0.5, true, 0, 0, {}, 0, 0}, {"mlp", 0, 0, false, 0, 0, {16, 8}, 200, 0}};
    options.selection = "maximum";
    k.options.encoded = EncodeClassifierOptions(options);
    ClassifierReportRecord report;
    report.classes = {"kitchen", "hall"};
    report.cross_validation = ClassifierCrossValidationRecord{};
    report.cross_validation->confusion = {{3, 1}, {0, 4}};
    report.cross_validation->setting_share = {{"svm(C=1,gamma=0.5/d)", 1.0}};
    k.report.encoded = EncodeClassifierReport(report);
    UpsertClassifier(c, k);
  });
  Open();
  const auto b = store_->Read([](Connection& c) { return GetCodebook(c, "home", "fpfh"); });
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->centres, (std::vector<float>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(b->seed, 7u);
  const auto r = store_->Read([](Connection& c) { return GetClassifier(c, "rooms", true); });
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->model, std::string("ESAM\0\x01", 6));
  const ClassifierOptionsRecord options = DecodeClassifierOptions(r->options.encoded, "options");
  ASSERT_EQ(options.base.size(), 2u);
  EXPECT_TRUE(options.base[0].svm_gamma_per_dim);
  EXPECT_EQ(options.base[1].mlp_hidden, (std::vector<int>{16, 8}));
  EXPECT_EQ(options.selection, "maximum");
  const auto listed = store_->Read([](Connection& c) { return ListClassifiers(c); });
  ASSERT_EQ(listed.size(), 1u);
  const ClassifierReportRecord report = DecodeClassifierReport(listed[0].report.encoded, "report");
  EXPECT_EQ(report.classes, (std::vector<std::string>{"kitchen", "hall"}));
  ASSERT_TRUE(report.cross_validation.has_value());
  EXPECT_EQ(report.cross_validation->confusion, (std::vector<std::vector<std::int64_t>>{{3, 1}, {0, 4}}));
  EXPECT_EQ(report.cross_validation->setting_share.at(0).second, 1.0);
}

}  // namespace
}  // namespace anchordb::storage
