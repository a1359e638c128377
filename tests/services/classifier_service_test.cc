// ClassifierService without HTTP on a real SQLite file (issue 35): training is validated before anything is queued,
// the trained model predicts, survives a new service on the same file, and classifies rooms of the map by the bags
// of words of their features over the map's codebook.
#include "services/classification/classifier_service.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <memory>

#include "schema/error.h"
#include "services/features/feature_service.h"
#include "services/grid/grid_service.h"
#include "tests/support/error_of.h"
#include "tests/support/temp_dir.h"
#include "tests/support/test_store.h"

namespace anchordb::services {
namespace classifier_service_test {

using testing::CodeOf;

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000LL;

class ClassifierServiceTest : public ::testing::Test {
 protected:
  ClassifierServiceTest() : clock_(kStartNs) {
    store_ = testing::OpenStoreWithMaps(dir_.File("classifiers.sqlite"), {"home"});
    grid_ = std::make_unique<GridService>(*store_, ServiceLimits{}, GridDefaults{}, clock_);
    jobs_ = std::make_unique<JobService>(*store_, JobSettings{}, clock_);
    features_ = std::make_unique<FeatureService>(*store_, *jobs_, FeatureSettings{}, clock_);
    classifiers_ = std::make_unique<ClassifierService>(*store_, *jobs_, *features_, *grid_, clock_);
  }
  // Ten samples per class of one feature type "x_toy" (2 numbers): `first` high for kitchens, low for bedrooms.
  static TrainClassifierRequest Training(int kitchen_peak) {
    TrainClassifierRequest r;
    r.name = "rooms";
    r.rounds = 5;
    r.folds = 2;
    r.seed = 3;
    for (int i = 0; i < 10; ++i) {
      const float high = 0.95f - 0.02f * static_cast<float>(i), low = 1.0f - high;
      std::vector<float> kitchen(2), bedroom(2);
      kitchen[kitchen_peak] = high;
      kitchen[1 - kitchen_peak] = low;
      bedroom[kitchen_peak] = low;
      bedroom[1 - kitchen_peak] = high;
      r.samples.push_back({"kitchen", {{"x_toy", kitchen}}});
      r.samples.push_back({"bedroom", {{"x_toy", bedroom}}});
    }
    return r;
  }
  void Train(const TrainClassifierRequest& r) {
    const JobTicket ticket = classifiers_->SubmitTraining(r);
    ASSERT_TRUE(jobs_->WaitIdle(120));
    const JobView done = jobs_->Get(ticket.job);
    ASSERT_EQ(done.status, JobStatus::kSucceeded) << done.error.value_or("");
  }
  std::int64_t Jobs() { return static_cast<std::int64_t>(jobs_->List(std::nullopt, 0, 1000).size()); }
  testing::TempDir dir_;
  FakeClock clock_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<GridService> grid_;
  std::unique_ptr<JobService> jobs_;
  std::unique_ptr<FeatureService> features_;
  std::unique_ptr<ClassifierService> classifiers_;
};

TEST_F(ClassifierServiceTest, BadTrainingRequestsQueueNothing) {
  TrainClassifierRequest one_class = Training(0);
  for (auto& s : one_class.samples) s.label = "kitchen";
  EXPECT_EQ(CodeOf([&] { classifiers_->SubmitTraining(one_class); }), ErrorCode::kUnprocessable);  // one class
  TrainClassifierRequest nan = Training(0);
  nan.samples[3].features["x_toy"][1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(CodeOf([&] { classifiers_->SubmitTraining(nan); }), ErrorCode::kInternal);
  TrainClassifierRequest ragged = Training(0);
  ragged.samples[4].features["x_toy"].push_back(0.5f);
  EXPECT_NE(CodeOf([&] { classifiers_->SubmitTraining(ragged); }), ErrorCode::kInternal);
  TrainClassifierRequest bad_name = Training(0);
  bad_name.name = "no spaces";
  EXPECT_EQ(CodeOf([&] { classifiers_->SubmitTraining(bad_name); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(Jobs(), 0);
  EXPECT_EQ(CodeOf([&] { classifiers_->Get("rooms"); }), ErrorCode::kNotFound);
}

TEST_F(ClassifierServiceTest, ATrainedModelPredictsAndSurvivesANewService) {
  Train(Training(0));
  const ClassifierView view = classifiers_->Get("rooms");
  EXPECT_EQ(view.feature_types, std::vector<std::string>{"x_toy"});
  EXPECT_EQ(view.feature_dims, std::vector<int>{2});
  EXPECT_EQ(view.classes.size(), 2u);
  PredictRequest p;
  p.samples = {{{"x_toy", {0.97f, 0.03f}}}, {{"x_toy", {0.04f, 0.96f}}}};
  const auto predicted = classifiers_->Predict("rooms", p);
  ASSERT_EQ(predicted.size(), 2u);
  EXPECT_EQ(predicted[0].label, "kitchen");
  EXPECT_EQ(predicted[1].label, "bedroom");
  PredictRequest wrong_length;
  wrong_length.samples = {{{"x_toy", {0.5f, 0.5f, 0.5f}}}};
  EXPECT_EQ(CodeOf([&] { classifiers_->Predict("rooms", wrong_length); }), ErrorCode::kInvalidArgument);

  // New services on the same file (a restart) load the stored model and answer the same.
  JobService jobs_again(*store_, JobSettings{}, clock_);
  FeatureService features_again(*store_, jobs_again, FeatureSettings{}, clock_);
  ClassifierService again(*store_, jobs_again, features_again, *grid_, clock_);
  const auto reloaded = again.Predict("rooms", p);
  ASSERT_EQ(reloaded.size(), 2u);
  EXPECT_EQ(reloaded[0].label, "kitchen");
  EXPECT_EQ(reloaded[0].distribution, predicted[0].distribution);
}

TEST_F(ClassifierServiceTest, RoomsAreClassifiedByTheBagsOfWordsOfTheirFeatures) {
  // Features of two kinds: near descriptor (0, 0) in the room x in [0, 2], near (10, 10) in the room x in [4, 6].
  FeatureBatch batch;
  batch.type = "x_toy";
  for (int i = 0; i < 6; ++i) batch.features.push_back({{0.01f * i, 0.0f}, {0.2 + 0.2 * i, 1.0, 0.5}, std::nullopt});
  for (int i = 0; i < 6; ++i) batch.features.push_back({{10.0f, 10.0f + 0.01f * i}, {4.2 + 0.2 * i, 1.0, 0.5}, std::nullopt});
  features_->AddBatch("home", batch);
  CodebookRequest codebook;
  codebook.type = "x_toy";
  codebook.words = 2;
  features_->SubmitCodebook("home", codebook);
  ASSERT_TRUE(jobs_->WaitIdle(60));
  const CodebookView book = features_->GetCodebook("home", "x_toy");
  ASSERT_EQ(book.centres.size(), 4u);
  const int low_word = book.centres[0] < 5.0f ? 0 : 1;  // the word of descriptors near (0, 0)
  // Kitchens are the rooms whose features are of the low word.
  Train(Training(low_word));

  ClassifyRoomsRequest rooms;
  rooms.map = "home";
  rooms.classifier = "rooms";
  rooms.regions = {{"west", {{0, 0}, {2, 0}, {2, 2}, {0, 2}}}, {"east", {{4, 0}, {6, 0}, {6, 2}, {4, 2}}}};
  const auto out = classifiers_->ClassifyRooms(rooms);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].id, "west");
  EXPECT_EQ(out[0].label, "kitchen");
  EXPECT_EQ(out[0].features, std::vector<int>{6});
  EXPECT_EQ(out[1].label, "bedroom");
  ClassifyRoomsRequest none = rooms;
  none.regions.clear();
  EXPECT_EQ(CodeOf([&] { classifiers_->ClassifyRooms(none); }), ErrorCode::kInvalidArgument);
  ClassifyRoomsRequest unknown = rooms;
  unknown.classifier = "nope";
  EXPECT_EQ(CodeOf([&] { classifiers_->ClassifyRooms(unknown); }), ErrorCode::kNotFound);
}

}  // namespace
}  // namespace anchordb::services
