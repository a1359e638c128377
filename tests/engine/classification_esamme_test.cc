#include "engine/classification/esamme.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "engine/classification/cross_validation.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace classification_esamme_test {

// K Gaussian classes in `dims` dimensions, class c centred at c * spacing on every axis, unit standard deviation;
// with `noise_dims` > 0 a second feature type "noise" of pure N(0, 1) values independent of the class.
TrainingSet Gaussians(int k, int per_class, int dims, double spacing, std::uint64_t seed, int noise_dims = 0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  TrainingSet data;
  for (int c = 0; c < k; ++c) data.class_names.push_back("c" + std::to_string(c));
  data.feature_types.push_back("signal");
  FeatureMatrix signal(k * per_class, dims);
  FeatureMatrix noise(k * per_class, std::max(noise_dims, 1));
  for (int c = 0; c < k; ++c) {
    for (int i = 0; i < per_class; ++i) {
      const int row = c * per_class + i;
      for (int d = 0; d < dims; ++d) signal(row, d) = static_cast<float>(c * spacing) + normal(rng);
      for (int d = 0; d < noise.cols(); ++d) noise(row, d) = normal(rng);
      data.labels.push_back(c);
    }
  }
  data.features.push_back(signal);
  if (noise_dims > 0) {
    data.feature_types.push_back("noise");
    data.features.push_back(noise);
  }
  return data;
}

BaseSetting Tree(int depth) {
  BaseSetting s;
  s.kind = BaseKind::kDTree;
  s.tree_max_depth = depth;
  return s;
}

BaseSetting Knn(int k) {
  BaseSetting s;
  s.kind = BaseKind::kKnn;
  s.knn_k = k;
  return s;
}

double TrainError(const EsammeModel& model, const TrainingSet& data) {
  const auto pred = PredictEsamme(model, data.features);
  int wrong = 0;
  for (std::size_t i = 0; i < pred.size(); ++i) wrong += pred[i].label != data.labels[i];
  return static_cast<double>(wrong) / static_cast<double>(pred.size());
}

TEST(EsammeTest, AlphaIsSammesAndZeroErrorIsClamped) {
  EXPECT_NEAR(SammeAlpha(0.25, 2, WeightUpdate::kThesis), std::log(3.0), 1e-12);
  EXPECT_NEAR(SammeAlpha(0.5, 4, WeightUpdate::kThesis), std::log(3.0), 1e-12);  // e = 0.5 still beats 3/4
  EXPECT_NEAR(SammeAlpha(0.0, 3, WeightUpdate::kThesis), std::log((1 - 1e-10) / 1e-10) + std::log(2.0), 1e-9);
  EXPECT_DOUBLE_EQ(SammeAlpha(0.0, 3, WeightUpdate::kSklearn), 1.0);
}

// A known property of SAMME: after scikit-learn's update the learner just chosen has weighted error (K-1)/K
// (chance). Eq. 4.10 as printed (x exp(-alpha) for the correct samples too) over-corrects: with K = 2 the learner's
// error becomes 1 - e, so its inverse is the best learner of the next round.
TEST(EsammeTest, ReweightingPutsTheLastLearnerAtChance) {
  for (int k : {2, 3, 6}) {
    std::vector<double> w{0.1, 0.2, 0.3, 0.15, 0.25};
    const std::vector<bool> wrong{true, false, false, true, false};
    const double e = 0.1 + 0.15;
    ReweightSamples(w, wrong, SammeAlpha(e, k, WeightUpdate::kSklearn), WeightUpdate::kSklearn);
    EXPECT_NEAR(w[0] + w[3], (k - 1.0) / k, 1e-12) << "K=" << k;
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3] + w[4], 1.0, 1e-12);
  }
  std::vector<double> w{0.1, 0.2, 0.3, 0.15, 0.25};
  ReweightSamples(w, {true, false, false, true, false}, SammeAlpha(0.25, 2, WeightUpdate::kThesis), WeightUpdate::kThesis);
  EXPECT_NEAR(w[0] + w[3], 0.75, 1e-12);
}

TEST(EsammeTest, SeparableClassesAreLearnedWithoutError) {
  const TrainingSet data = Gaussians(3, 40, 2, 8.0, 11);
  EsammeOptions options;
  options.base = {Tree(1)};
  options.rounds = 30;
  const EsammeModel model = TrainEsamme(data, options);
  EXPECT_EQ(TrainError(model, data), 0.0);
  const auto report = CrossValidate(data, options, StratifiedFolds(data.labels, 5, 3));
  EXPECT_LE(report.test_error, 0.02);
  ASSERT_EQ(report.confusion.size(), 3u);
  int total = 0;
  for (const auto& row : report.confusion) for (int v : row) total += v;
  EXPECT_EQ(total, 120);  // every sample tested once
}

// Two unit Gaussians 2 apart in 1-D: the Bayes error is Phi(-1) = 0.159; boosted stumps must come near it, not 0.
TEST(EsammeTest, OverlappingClassesApproachTheBayesError) {
  const TrainingSet data = Gaussians(2, 300, 1, 2.0, 5);
  EsammeOptions options;
  options.base = {Tree(1)};
  options.rounds = 20;
  options.selection = Selection::kWeights;
  options.update = WeightUpdate::kSklearn;  // SAMME as Zhu et al. (2009) wrote it
  const auto report = CrossValidate(data, options, StratifiedFolds(data.labels, 5, 9));
  EXPECT_GT(report.test_error, 0.12);
  EXPECT_LT(report.test_error, 0.21);
  EXPECT_LE(report.train_error_per_round.back(), report.test_error_per_round.back() + 0.02);
}

// A feature type of pure noise is chosen far less often than the signal (a blind pick of the two would be 0.5). With
// the whole-set error (the default) a noise learner still wins some late rounds, since the error counts the
// resample it fitted (KNN, depth-3 tree) as right once the weight sits on those samples: 0.149 of the rounds here,
// test error 0.067 (0.038 and 0.092 while the maximum selection broke ties by the lower index, which left class 2
// out of the first resample). Judged out of bag it is never chosen (0.000; the lower-index rule threw here).
TEST(EsammeTest, PureNoiseFeatureTypeIsRarelyChosen) {
  const TrainingSet data = Gaussians(3, 40, 3, 2.5, 21, 3);
  EsammeOptions options;
  options.base = {Tree(1), Tree(3), Knn(5)};
  options.rounds = 25;
  auto noise_share_of = [](const CrossValidationReport& report) {
    double noise_share = 0.0;
    for (const auto& [type, share] : report.feature_share) if (type == "noise") noise_share = share;
    return noise_share;
  };
  const auto report = CrossValidate(data, options, StratifiedFolds(data.labels, 5, 4));
  EXPECT_LT(noise_share_of(report), 0.25);
  EXPECT_LT(report.test_error, 0.1);  // chance is 0.67
  options.error_on = ErrorMeasure::kOutOfBag;
  const auto out_of_bag = CrossValidate(data, options, StratifiedFolds(data.labels, 5, 4));
  EXPECT_LT(noise_share_of(out_of_bag), 0.05);
  EXPECT_LT(out_of_bag.test_error, 0.1);
}

TEST(EsammeTest, ZeroErrorKeepsTheLearnerAndStops) {
  const TrainingSet data = Gaussians(3, 30, 2, 10.0, 2);
  EsammeOptions options;
  options.base = {Tree(4)};
  options.rounds = 10;
  options.selection = Selection::kWeights;
  const EsammeModel model = TrainEsamme(data, options);
  ASSERT_EQ(model.rounds.size(), 1u);
  EXPECT_EQ(model.rounds[0].error, 0.0);
  EXPECT_NEAR(model.rounds[0].alpha, SammeAlpha(0.0, 3, WeightUpdate::kThesis), 1e-9);
}

// Maximum selection among equal weights (the first round, or any tie) takes a seeded random order, not the lower
// index: on class-sorted samples the first 60 % would hold the first classes only.
TEST(EsammeTest, MaximumSelectionBreaksTiesAtRandomWithTheSeed) {
  const std::vector<double> equal(60, 1.0 / 60);  // samples 0-19 class 0, 20-39 class 1, 40-59 class 2
  std::mt19937_64 rng(1);
  const std::vector<int> pick = MaximumSelection(equal, 36, rng);
  ASSERT_EQ(pick.size(), 36u);
  EXPECT_TRUE(std::is_sorted(pick.begin(), pick.end()));
  EXPECT_EQ(std::adjacent_find(pick.begin(), pick.end()), pick.end());  // each sample at most once
  int per_class[3] = {0, 0, 0};
  for (int i : pick) ++per_class[i / 20];
  for (int c = 0; c < 3; ++c) EXPECT_GT(per_class[c], 0) << "class " << c;
  EXPECT_GT(pick.back(), 35);  // the old rule picked exactly 0..35
  std::mt19937_64 same(1), other(2);
  EXPECT_EQ(MaximumSelection(equal, 36, same), pick);
  EXPECT_NE(MaximumSelection(equal, 36, other), pick);
  // Greater weights still come first: the 5 heaviest samples are always in, whatever the order among the others.
  std::vector<double> w(60, 0.01);
  for (int i : {3, 17, 41, 50, 59}) w[static_cast<std::size_t>(i)] = 0.02;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 r(seed);
    const std::vector<int> p = MaximumSelection(w, 8, r);
    ASSERT_EQ(p.size(), 8u);
    for (int i : {3, 17, 41, 50, 59}) EXPECT_TRUE(std::binary_search(p.begin(), p.end(), i)) << i;
  }
  std::mt19937_64 r(3);
  EXPECT_EQ(MaximumSelection(w, 100, r).size(), 60u);  // z beyond n: every sample
}

// One round of maximum selection on class-sorted training data sees every class, so its learner predicts every class
// (with lower-index-first ties the resample held classes 0 and 1 only and class 2 was never predicted); and the same
// seed gives the same model.
TEST(EsammeTest, MaximumSelectionOnClassSortedDataSeesEveryClass) {
  const TrainingSet data = Gaussians(3, 30, 2, 10.0, 2);
  EsammeOptions options;
  options.base = {Tree(4)};
  options.rounds = 1;
  options.selection = Selection::kMaximum;
  options.sample_factor = 0.6;
  const EsammeModel model = TrainEsamme(data, options);
  std::set<int> predicted;
  for (const auto& p : PredictEsamme(model, data.features)) predicted.insert(p.label);
  EXPECT_EQ(predicted, (std::set<int>{0, 1, 2}));
  EXPECT_LT(TrainError(model, data), 0.05);
  options.rounds = 5;
  EXPECT_EQ(EncodeEsamme(TrainEsamme(data, options)), EncodeEsamme(TrainEsamme(data, options)));
}

// Out of bag, a learner that interpolates its resample (1-NN) is judged on the samples it did not see: with the same
// seed (the same resamples) its first-round error is higher than the whole-set error, which counts its own training
// samples as right.
TEST(EsammeTest, OutOfBagErrorJudgesAnInterpolatingLearnerOnUnseenSamples) {
  const TrainingSet data = Gaussians(2, 60, 2, 1.0, 17);  // overlapping: 1-NN errs on unseen samples
  EsammeOptions o;
  o.base = {Knn(1)};
  o.selection = Selection::kRoulette;
  o.rounds = 1;
  o.update = WeightUpdate::kSklearn;
  const EsammeModel whole = TrainEsamme(data, o);
  o.error_on = ErrorMeasure::kOutOfBag;
  const EsammeModel oob = TrainEsamme(data, o);
  ASSERT_EQ(whole.rounds.size(), 1u);
  ASSERT_EQ(oob.rounds.size(), 1u);
  EXPECT_GT(whole.rounds[0].error, 0.0);
  EXPECT_GT(oob.rounds[0].error, whole.rounds[0].error * 1.4);  // about 45 % of the samples are out of bag
  EXPECT_LT(oob.rounds[0].alpha, whole.rounds[0].alpha);
}

// e = 0 out of bag is floored at half a sample's share and training goes on; under the whole-set error the same
// perfect learner ends training after one round. The learning rate scales alpha.
TEST(EsammeTest, ZeroOutOfBagErrorIsFlooredAndTrainingGoesOn) {
  const TrainingSet data = Gaussians(2, 30, 2, 20.0, 5);  // separable
  EsammeOptions o;
  o.base = {Tree(1)};
  o.selection = Selection::kRoulette;
  o.rounds = 5;
  o.update = WeightUpdate::kSklearn;
  EXPECT_EQ(TrainEsamme(data, o).rounds.size(), 1u);
  o.error_on = ErrorMeasure::kOutOfBag;
  const EsammeModel oob = TrainEsamme(data, o);
  ASSERT_EQ(oob.rounds.size(), 5u);
  for (const auto& r : oob.rounds) {
    EXPECT_GT(r.error, 0.5 / 60);  // 1/(2m), m < 60 samples out of bag
    EXPECT_LT(r.error, 0.5 / 10);
    EXPECT_NEAR(r.alpha, SammeAlpha(r.error, 2, WeightUpdate::kSklearn), 1e-12);
  }
  EXPECT_EQ(TrainError(oob, data), 0.0);
  o.learning_rate = 0.5;
  const EsammeModel shrunk = TrainEsamme(data, o);
  ASSERT_EQ(shrunk.rounds.size(), 5u);
  EXPECT_NEAR(shrunk.rounds[0].alpha, 0.5 * oob.rounds[0].alpha, 1e-12);
  o.learning_rate = 0.0;
  EXPECT_THROW(TrainEsamme(data, o), Error);
}

TEST(EsammeTest, NoLearnerBetterThanChanceIsAnError) {
  TrainingSet data = Gaussians(2, 20, 1, 0.0, 3);
  for (int i = 0; i < data.features[0].rows(); ++i) data.features[0](i, 0) = 1.0f;  // nothing to learn from
  EsammeOptions options;
  options.base = {Tree(1)};
  try {
    TrainEsamme(data, options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnprocessable);
  }
}

TEST(EsammeTest, EveryKindRoundTripsThroughTheBlob) {
  const TrainingSet data = Gaussians(3, 30, 4, 2.0, 8, 2);
  EsammeOptions options;
  options.base = SvmGrid({1.0}, {0.1});
  options.base.push_back(Tree(2));
  BaseSetting mlp;
  mlp.kind = BaseKind::kMlp;
  mlp.mlp_hidden = {8};
  mlp.mlp_iterations = 50;
  options.base.push_back(mlp);
  options.base.push_back(Knn(3));
  options.rounds = 6;
  const EsammeModel model = TrainEsamme(data, options);
  const std::string blob = EncodeEsamme(model);
  const EsammeModel back = DecodeEsamme(blob);
  ASSERT_EQ(back.rounds.size(), model.rounds.size());
  EXPECT_EQ(back.class_names, model.class_names);
  const TrainingSet probe = Gaussians(3, 10, 4, 2.0, 99, 2);
  const auto a = PredictEsamme(model, probe.features);
  const auto b = PredictEsamme(back, probe.features);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].label, b[i].label);
    EXPECT_EQ(a[i].distribution, b[i].distribution);
  }
  // Every round's own base classifier predicts the same after the round trip, whatever its kind.
  EXPECT_EQ(PredictRounds(model, probe.features), PredictRounds(back, probe.features));
  EXPECT_EQ(EncodeEsamme(back), blob);
  std::string damaged = blob;
  damaged.resize(blob.size() / 2);
  EXPECT_THROW(DecodeEsamme(damaged), Error);
  EXPECT_THROW(DecodeEsamme("not a model"), Error);
}

TEST(EsammeTest, SvmGammaPerDimensionIsGammaOverTheDescriptorLength) {
  const TrainingSet data = Gaussians(3, 30, 8, 1.0, 5);
  EsammeOptions per_dim, absolute;
  per_dim.base = SvmGrid({1.0}, {1.0}, true);
  absolute.base = SvmGrid({1.0}, {1.0 / 8});
  for (EsammeOptions* o : {&per_dim, &absolute}) {
    o->selection = Selection::kRoulette;
    o->rounds = 4;
  }
  EXPECT_EQ(per_dim.base[0].Name(), "svm(C=1,gamma=1/d)");
  EXPECT_EQ(absolute.base[0].Name(), "svm(C=1,gamma=0.125)");
  const EsammeModel model = TrainEsamme(data, per_dim);
  // The same kernel as gamma 1/8 on these 8 dimensions: every round predicts the same.
  EXPECT_EQ(PredictRounds(model, data.features), PredictRounds(TrainEsamme(data, absolute), data.features));
  // The setting survives the blob (version 2).
  const EsammeModel back = DecodeEsamme(EncodeEsamme(model));
  ASSERT_EQ(back.settings.size(), 1u);
  EXPECT_TRUE(back.settings[0].svm_gamma_per_dim);
  EXPECT_EQ(back.settings[0].Name(), "svm(C=1,gamma=1/d)");
  EXPECT_EQ(PredictRounds(back, data.features), PredictRounds(model, data.features));
}

TEST(EsammeTest, SameSeedSameModel) {
  const TrainingSet data = Gaussians(3, 25, 2, 1.5, 4);
  EsammeOptions options;
  options.base = {Tree(1), Tree(2)};
  options.selection = Selection::kRoulette;
  options.rounds = 8;
  EXPECT_EQ(EncodeEsamme(TrainEsamme(data, options)), EncodeEsamme(TrainEsamme(data, options)));
}

TEST(EsammeTest, UnknownClassFromNegativesAndLowShare) {
  TrainingSet data = Gaussians(3, 30, 2, 6.0, 6);
  data.class_names[2] = kUnknownClass;  // the third cluster are negative examples
  EsammeOptions options;
  options.base = {Tree(1)};  // a depth-2 tree separates the three clusters at once (e = 0, one unanimous round)
  options.rounds = 15;
  options.unknown = true;
  options.unknown_min_share = 0.999;  // nothing short of a unanimous vote is accepted
  const EsammeModel model = TrainEsamme(data, options);
  FeatureMatrix between(1, 2);
  between << 3.0f, 9.0f;  // between class 0/1 on one axis, near the unknown cluster on the other
  const auto pred = PredictEsamme(model, {between});
  EXPECT_EQ(model.class_names[static_cast<std::size_t>(pred[0].label)], kUnknownClass);
  EsammeOptions no_unknown_class = options;
  data.class_names[2] = "c2";
  EXPECT_THROW(TrainEsamme(data, no_unknown_class), Error);
}

TEST(EsammeTest, BadInputIsRefused) {
  const TrainingSet good = Gaussians(2, 10, 2, 3.0, 1);
  EsammeOptions options;
  options.base = {Tree(1)};
  auto code_of = [&](TrainingSet data, EsammeOptions o) {
    try {
      TrainEsamme(data, o);
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::kInternal;
  };
  TrainingSet nan = good;
  nan.features[0](3, 1) = std::nanf("");
  EXPECT_EQ(code_of(nan, options), ErrorCode::kInvalidArgument);
  TrainingSet one_class = good;
  for (int& l : one_class.labels) l = 0;
  EXPECT_EQ(code_of(one_class, options), ErrorCode::kUnprocessable);
  TrainingSet ragged = good;
  ragged.features[0].conservativeResize(5, 2);
  EXPECT_EQ(code_of(ragged, options), ErrorCode::kInvalidArgument);
  EsammeOptions absurd = options;
  absurd.rounds = 100000;
  EXPECT_EQ(code_of(good, absurd), ErrorCode::kInvalidArgument);
  absurd = options;
  absurd.sample_factor = 0.0;
  EXPECT_EQ(code_of(good, absurd), ErrorCode::kInvalidArgument);
  absurd = options;
  absurd.base[0].tree_max_depth = 0;
  EXPECT_EQ(code_of(good, absurd), ErrorCode::kInvalidArgument);
  EXPECT_THROW(StratifiedFolds(good.labels, 21, 1), Error);  // folds > samples
  FeatureMatrix wrong_length(1, 3);
  wrong_length.setZero();
  EXPECT_THROW(PredictEsamme(TrainEsamme(good, options), {wrong_length}), Error);
}

TEST(EsammeTest, TrainingCanBeCancelled) {
  const TrainingSet data = Gaussians(2, 50, 1, 1.0, 7);
  EsammeOptions options;
  options.base = {Tree(1)};
  options.rounds = 20;
  options.selection = Selection::kRoulette;  // maximum selection ends this K = 2 overlap after one round (eq. 4.10)
  int calls = 0;
  try {
    TrainEsamme(data, options, [&](int done, int) { ++calls; return done < 3; });
    FAIL() << "expected cancellation";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kConflict);
  }
  EXPECT_EQ(calls, 3);
}

TEST(EsammeTest, StratifiedFoldsBalanceClasses) {
  std::vector<int> labels;
  for (int i = 0; i < 50; ++i) labels.push_back(i < 30 ? 0 : 1);
  const auto folds = StratifiedFolds(labels, 5, 17);
  for (int f = 0; f < 5; ++f) {
    int zeros = 0, ones = 0;
    for (std::size_t i = 0; i < labels.size(); ++i) if (folds[i] == f) (labels[i] ? ones : zeros)++;
    EXPECT_EQ(zeros, 6);
    EXPECT_EQ(ones, 4);
  }
  EXPECT_EQ(folds, StratifiedFolds(labels, 5, 17));
}

}  // namespace
}  // namespace anchordb::engine
