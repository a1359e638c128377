// FeatureService without HTTP on a real SQLite file (issue 35): a client batch is de-duplicated against what is
// stored and within itself, a bad batch is refused naming the field and stores nothing, spatial queries and their
// bad bounds, and the codebook job: too few features refused, a codebook whose every word is a stored descriptor,
// codewords given to the stored features and to later ones on insert, and a bag of words over a region.
#include "services/features/feature_service.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <set>

#include "schema/error.h"
#include "tests/support/error_of.h"
#include "tests/support/temp_dir.h"
#include "tests/support/test_store.h"

namespace anchordb::services {
namespace feature_service_test {

using testing::ErrorOf;

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000LL;

class FeatureServiceTest : public ::testing::Test {
 protected:
  FeatureServiceTest() : clock_(kStartNs) {
    store_ = testing::OpenStoreWithMaps(dir_.File("features.sqlite"), {"home"});
    jobs_ = std::make_unique<JobService>(*store_, JobSettings{}, clock_);
    features_ = std::make_unique<FeatureService>(*store_, *jobs_, FeatureSettings{}, clock_);
  }
  // A client type ("other" thresholds: 2 cm, descriptors equal) of dimension 2.
  static FeatureItem Item(float a, float b, const Eigen::Vector3d& anchor_m) { return {{a, b}, anchor_m, std::nullopt}; }
  FeatureBatchResult Add(std::vector<FeatureItem> items, const std::string& type = "x_toy") {
    FeatureBatch batch;
    batch.type = type;
    batch.features = std::move(items);
    return features_->AddBatch("home", batch);
  }
  int Stored() {
    FeatureQuery q;
    q.limit = 10000;
    return static_cast<int>(features_->List("home", q).features.size());
  }
  testing::TempDir dir_;
  FakeClock clock_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<JobService> jobs_;
  std::unique_ptr<FeatureService> features_;
};

TEST_F(FeatureServiceTest, ABatchIsDeduplicatedAgainstTheStoreAndWithinItself) {
  const FeatureBatchResult first = Add({Item(1, 0, {0, 0, 0}), Item(0, 1, {1, 0, 0})});
  EXPECT_EQ(first.inserted, 2);
  EXPECT_EQ(first.duplicates, 0);
  // The same descriptor 1 cm from a stored one is a repeat of it; 5 cm away, or another descriptor, is new; the
  // batch's own repeat of its new item points at that item.
  const FeatureBatchResult second =
      Add({Item(1, 0, {0.01, 0, 0}), Item(1, 0, {0.05, 0, 0}), Item(0, 1, {0, 0, 0}), Item(1, 0, {0.051, 0, 0})});
  EXPECT_EQ(second.inserted, 2);
  EXPECT_EQ(second.duplicates, 2);
  ASSERT_EQ(second.ids.size(), 4u);
  EXPECT_EQ(second.ids[0], first.ids[0]);
  EXPECT_TRUE(second.duplicate[0]);
  EXPECT_FALSE(second.duplicate[1]);
  EXPECT_FALSE(second.duplicate[2]);
  EXPECT_TRUE(second.duplicate[3]);
  EXPECT_EQ(second.ids[3], second.ids[1]);
  EXPECT_EQ(Stored(), 4);
}

TEST_F(FeatureServiceTest, ABadBatchIsRefusedNamingTheFieldAndStoresNothing) {
  Add({Item(1, 0, {0, 0, 0})});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // One good item before the bad one: the whole batch goes nowhere.
  Error e = ErrorOf([&] { Add({Item(0, 1, {2, 0, 0}), Item(nan, 1, {3, 0, 0})}); });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(e.field().find("features"), std::string::npos) << e.field();
  e = ErrorOf([&] { Add({Item(0, 1, {2, 0, 0}), {{1, 2, 3}, {3, 0, 0}, std::nullopt}}); });  // 3 numbers, not 2
  EXPECT_NE(e.field().find("features"), std::string::npos) << e.field();
  e = ErrorOf([&] { Add({{{1, 2}, {3, 0, 0}, std::int64_t{999}}}); });  // no such keyframe
  EXPECT_NE(e.code(), ErrorCode::kInternal);
  EXPECT_EQ(ErrorOf([&] { Add({Item(1, 0, {0, 0, 0})}, "fpfh"); }).code(), ErrorCode::kUnprocessable);  // fpfh has 33
  FeatureBatch other_map;
  other_map.type = "x_toy";
  other_map.features = {Item(0, 1, {2, 0, 0})};
  EXPECT_EQ(ErrorOf([&] { features_->AddBatch("nowhere", other_map); }).code(), ErrorCode::kNotFound);
  EXPECT_EQ(Stored(), 1);
}

TEST_F(FeatureServiceTest, QueriesFindWhatIsInsideAndRefuseBadBounds) {
  Add({Item(1, 0, {0, 0, 0}), Item(0, 1, {1, 0, 0}), Item(1, 1, {3, 0, 0})});
  FeatureQuery near;
  near.near_m = Eigen::Vector3d(0.9, 0, 0);
  near.radius_m = 1.0;
  std::set<float> first_numbers;
  for (const Feature& f : features_->List("home", near).features) first_numbers.insert(f.descriptor.at(0));
  EXPECT_EQ(first_numbers, (std::set<float>{1.0f, 0.0f}));  // the features at 0 and 1 m, not the one at 3 m
  FeatureQuery page;
  page.limit = 2;
  const FeaturePage p = features_->List("home", page);
  EXPECT_EQ(p.features.size(), 2u);
  ASSERT_TRUE(p.next_after.has_value());
  page.after_id = *p.next_after;
  EXPECT_EQ(features_->List("home", page).features.size(), 1u);
  FeatureQuery bad;
  bad.limit = 0;
  EXPECT_EQ(ErrorOf([&] { features_->List("home", bad); }).code(), ErrorCode::kInvalidArgument);
  bad.limit = 10;
  bad.box_min_m = Eigen::Vector3d(1, 1, 1);
  bad.box_max_m = Eigen::Vector3d(0, 0, 0);
  EXPECT_EQ(ErrorOf([&] { features_->List("home", bad); }).code(), ErrorCode::kInvalidArgument);
}

TEST_F(FeatureServiceTest, ACodebookJobGivesEveryFeatureItsWordAndBagsOfWordsCountThem) {
  // Two tight clusters of descriptors: around (0, 0) at x < 1 m and around (10, 10) at x > 5 m.
  std::vector<FeatureItem> items;
  for (int i = 0; i < 6; ++i) items.push_back(Item(0.01f * i, 0.0f, {0.1 * i, 0, 0}));
  for (int i = 0; i < 4; ++i) items.push_back(Item(10.0f, 10.0f + 0.01f * i, {6.0 + 0.1 * i, 0, 0}));
  Add(items);
  CodebookRequest too_many;
  too_many.type = "x_toy";
  too_many.words = 11;
  EXPECT_EQ(ErrorOf([&] { features_->SubmitCodebook("home", too_many); }).code(), ErrorCode::kUnprocessable);
  EXPECT_EQ(ErrorOf([&] { features_->GetCodebook("home", "x_toy"); }).code(), ErrorCode::kNotFound);

  CodebookRequest request;
  request.type = "x_toy";
  request.words = 2;
  request.seed = 7;
  const JobTicket ticket = features_->SubmitCodebook("home", request);
  ASSERT_TRUE(jobs_->WaitIdle(60));
  ASSERT_EQ(jobs_->Get(ticket.job).status, JobStatus::kSucceeded) << jobs_->Get(ticket.job).error.value_or("");
  const CodebookView book = features_->GetCodebook("home", "x_toy");
  EXPECT_EQ(book.words, 2);
  EXPECT_EQ(book.dims, 2);
  EXPECT_EQ(book.features, 10);
  ASSERT_EQ(book.centres.size(), 4u);
  // One centre per cluster.
  const bool first_low = book.centres[0] < 5.0f;
  EXPECT_NE(first_low, book.centres[2] < 5.0f);

  // Every stored feature has the word of its cluster, and a later insert gets one too.
  Add({Item(10.0f, 10.5f, {7, 0, 0})});
  FeatureQuery all;
  all.limit = 100;
  int low_word = -1, high_word = -1;
  for (const Feature& f : features_->List("home", all).features) {
    ASSERT_TRUE(f.codeword.has_value()) << "feature " << f.id;
    int& word = f.descriptor[0] < 5.0f ? low_word : high_word;
    if (word < 0) word = *f.codeword;
    EXPECT_EQ(*f.codeword, word) << "feature " << f.id;
  }
  EXPECT_NE(low_word, high_word);

  // The bag of words of x in [-1, 1]: the six low features, all of one word.
  BowQuery box;
  box.type = "x_toy";
  box.box_min_m = Eigen::Vector3d(-1, -1, -1);
  box.box_max_m = Eigen::Vector3d(1, 1, 1);
  const BowResult bow = features_->BagOfWords("home", box);
  EXPECT_EQ(bow.features, 6);
  ASSERT_EQ(bow.histogram.size(), 2u);
  EXPECT_DOUBLE_EQ(bow.histogram[static_cast<std::size_t>(low_word)], 1.0);
  EXPECT_DOUBLE_EQ(bow.histogram[static_cast<std::size_t>(high_word)], 0.0);
  BowQuery two_regions = box;
  two_regions.near_m = Eigen::Vector3d::Zero();
  two_regions.radius_m = 1.0;
  EXPECT_EQ(ErrorOf([&] { features_->BagOfWords("home", two_regions); }).code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace anchordb::services
