#include "engine/classification/esamme.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

constexpr double kZeroErrorClamp = 1e-10;

FeatureScaling FitScaling(const FeatureMatrix& x) {
  FeatureScaling s;
  const auto n = static_cast<double>(x.rows());
  s.mean = x.colwise().mean().transpose();
  s.inv_std = Eigen::VectorXf::Zero(x.cols());
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const double var = (x.col(j).array() - s.mean(j)).square().cast<double>().sum() / std::max(1.0, n);
    const double sd = std::sqrt(var);
    s.inv_std(j) = sd > 1e-12 ? static_cast<float>(1.0 / sd) : 0.0f;
  }
  return s;
}

FeatureMatrix Apply(const FeatureScaling& s, const FeatureMatrix& x) {
  FeatureMatrix out = x;
  out.rowwise() -= s.mean.transpose();
  out.array().rowwise() *= s.inv_std.transpose().array();
  return out;
}

FeatureMatrix Rows(const FeatureMatrix& x, const std::vector<int>& idx) {
  FeatureMatrix out(static_cast<Eigen::Index>(idx.size()), x.cols());
  for (std::size_t i = 0; i < idx.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = x.row(idx[i]);
  return out;
}

std::vector<int> RouletteSelection(const std::vector<double>& w, int z, std::mt19937_64& rng) {
  std::vector<double> cumulative(w.size());
  std::partial_sum(w.begin(), w.end(), cumulative.begin());
  const double total = cumulative.back();
  std::vector<int> out;
  out.reserve(static_cast<std::size_t>(z));
  for (int i = 0; i < z; ++i) {
    // 53 random bits -> [0, total): portable, unlike std::uniform_real_distribution.
    const double r = static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0) * total;
    auto it = std::upper_bound(cumulative.begin(), cumulative.end(), r);
    if (it == cumulative.end()) --it;
    out.push_back(static_cast<int>(it - cumulative.begin()));
  }
  return out;
}

// The weighted share of the mistakes among the samples that `skip` (empty: none) does not mark; NaN when those
// samples carry no weight.
double WeightedError(const std::vector<double>& w, const std::vector<bool>& mistakes, const std::vector<bool>& skip) {
  double wrong = 0.0, total = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (!skip.empty() && skip[i]) continue;
    total += w[i];
    if (mistakes[i]) wrong += w[i];
  }
  return total > 0 ? wrong / total : std::numeric_limits<double>::quiet_NaN();
}

void CheckFinite(const FeatureMatrix& x, const std::string& field) {
  if (!x.allFinite()) throw Error(ErrorCode::kInvalidArgument, "features must be finite numbers", field);
}

}  // namespace

const char* SelectionName(Selection s) {
  switch (s) {
    case Selection::kMaximum: return "maximum";
    case Selection::kRoulette: return "roulette";
    case Selection::kWeights: return "weights";
  }
  return "?";
}

Selection ParseSelection(const std::string& name) {
  for (Selection s : {Selection::kMaximum, Selection::kRoulette, Selection::kWeights}) {
    if (name == SelectionName(s)) return s;
  }
  throw Error(ErrorCode::kInvalidArgument, "selection must be maximum, roulette or weights", "selection");
}

const char* WeightUpdateName(WeightUpdate u) { return u == WeightUpdate::kThesis ? "thesis" : "sklearn"; }

const char* ErrorMeasureName(ErrorMeasure m) { return m == ErrorMeasure::kWhole ? "whole" : "out_of_bag"; }

ErrorMeasure ParseErrorMeasure(const std::string& name) {
  if (name == "whole") return ErrorMeasure::kWhole;
  if (name == "out_of_bag") return ErrorMeasure::kOutOfBag;
  throw Error(ErrorCode::kInvalidArgument, "error_on must be whole or out_of_bag", "error_on");
}

WeightUpdate ParseWeightUpdate(const std::string& name) {
  if (name == "thesis") return WeightUpdate::kThesis;
  if (name == "sklearn") return WeightUpdate::kSklearn;
  throw Error(ErrorCode::kInvalidArgument, "update must be thesis or sklearn", "update");
}

std::vector<int> MaximumSelection(const std::vector<double>& weights, int z, std::mt19937_64& rng) {
  // A seeded Fisher-Yates shuffle (portable, unlike std::shuffle) puts equal weights in random order; the stable
  // sort by weight keeps that order among them.
  std::vector<int> order(weights.size());
  std::iota(order.begin(), order.end(), 0);
  for (std::size_t i = order.size(); i > 1; --i) {
    const std::size_t j = static_cast<std::size_t>(rng() % i);
    std::swap(order[i - 1], order[j]);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return weights[static_cast<std::size_t>(a)] > weights[static_cast<std::size_t>(b)];
  });
  order.resize(static_cast<std::size_t>(std::clamp(z, 0, static_cast<int>(order.size()))));
  std::sort(order.begin(), order.end());
  return order;
}

void ValidateTraining(const TrainingSet& data, const EsammeOptions& options) {
  if (options.base.empty()) throw Error(ErrorCode::kInvalidArgument, "at least one base classifier setting", "base");
  for (std::size_t i = 0; i < options.base.size(); ++i) {
    ValidateBaseSetting(options.base[i], "base[" + std::to_string(i) + "]");
  }
  if (options.rounds < 1 || options.rounds > 1000) {
    throw Error(ErrorCode::kInvalidArgument, "rounds must be in [1, 1000]", "rounds");
  }
  if (!(options.sample_factor > 0.0 && options.sample_factor <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument, "sample_factor must be in (0, 1]", "sample_factor");
  }
  if (!(options.learning_rate > 0.0 && options.learning_rate <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument, "learning_rate must be in (0, 1]", "learning_rate");
  }
  if (!(options.unknown_min_share >= 0.0 && options.unknown_min_share <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument, "unknown_min_share must be in [0, 1]", "unknown_min_share");
  }
  const std::set<std::string> names(data.class_names.begin(), data.class_names.end());
  if (names.size() != data.class_names.size()) throw Error(ErrorCode::kInvalidArgument, "class names must be distinct", "samples");
  const std::set<std::string> types(data.feature_types.begin(), data.feature_types.end());
  if (types.empty() || types.size() != data.feature_types.size() || data.features.size() != data.feature_types.size()) {
    throw Error(ErrorCode::kInvalidArgument, "one or more distinct feature types, one matrix each", "samples");
  }
  const std::size_t n = data.labels.size();
  if (n == 0) throw Error(ErrorCode::kUnprocessable, "no training samples", "samples");
  for (std::size_t t = 0; t < data.features.size(); ++t) {
    if (static_cast<std::size_t>(data.features[t].rows()) != n || data.features[t].cols() < 1) {
      throw Error(ErrorCode::kInvalidArgument, "feature type '" + data.feature_types[t] + "' needs one descriptor per sample",
                  "samples");
    }
    CheckFinite(data.features[t], "samples");
  }
  std::vector<int> counts(data.class_names.size(), 0);
  for (int l : data.labels) {
    if (l < 0 || static_cast<std::size_t>(l) >= counts.size()) throw Error(ErrorCode::kInvalidArgument, "label out of range", "samples");
    ++counts[static_cast<std::size_t>(l)];
  }
  if (std::count_if(counts.begin(), counts.end(), [](int c) { return c > 0; }) < 2) {
    throw Error(ErrorCode::kUnprocessable, "training needs samples of at least two classes", "samples");
  }
  if (options.unknown && !names.contains(kUnknownClass)) {
    throw Error(ErrorCode::kInvalidArgument, "unknown needs the class 'unknown' among the classes", "unknown");
  }
}

double SammeAlpha(double error, int num_classes, WeightUpdate update) {
  if (error <= 0.0 && update == WeightUpdate::kSklearn) return 1.0;
  const double e = std::max(error, kZeroErrorClamp);
  return std::log((1.0 - e) / e) + std::log(static_cast<double>(num_classes - 1));
}

void ReweightSamples(std::vector<double>& weights, const std::vector<bool>& wrong, double alpha, WeightUpdate update) {
  double sum = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (update == WeightUpdate::kThesis) {
      weights[i] *= std::exp(wrong[i] ? alpha : -alpha);
    } else if (wrong[i]) {
      weights[i] *= std::exp(alpha);
    }
    sum += weights[i];
  }
  if (sum > 0) for (double& w : weights) w /= sum;
}

EsammeModel TrainEsamme(const TrainingSet& data, const EsammeOptions& options, const RoundCallback& callback) {
  ValidateTraining(data, options);
  const int n = static_cast<int>(data.labels.size());
  const int k = static_cast<int>(data.class_names.size());
  EsammeModel model;
  model.class_names = data.class_names;
  model.feature_types = data.feature_types;
  model.settings = options.base;
  model.unknown = options.unknown;
  model.unknown_min_share = options.unknown_min_share;
  std::vector<FeatureMatrix> scaled;
  for (const auto& x : data.features) {
    model.feature_dims.push_back(static_cast<int>(x.cols()));
    model.scaling.push_back(FitScaling(x));
    scaled.push_back(Apply(model.scaling.back(), x));
  }
  std::vector<double> w(static_cast<std::size_t>(n), 1.0 / n);
  std::mt19937_64 rng(options.seed);
  const int z = std::clamp(static_cast<int>(std::lround(options.sample_factor * n)), std::min(k, n), n);
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  const double chance = static_cast<double>(k - 1) / k;

  for (int round = 0; round < options.rounds; ++round) {
    const std::vector<int> subset = options.selection == Selection::kMaximum ? MaximumSelection(w, z, rng)
                                                                             : RouletteSelection(w, z, rng);
    std::vector<float> w_all(w.begin(), w.end());
    std::vector<bool> in_subset(static_cast<std::size_t>(n), false);
    for (int i : subset) in_subset[static_cast<std::size_t>(i)] = true;
    double best_error = std::numeric_limits<double>::infinity();
    EsammeRound best;
    std::vector<bool> best_wrong;
    int best_measured_on = n;  // samples the best error was measured on
    for (int s = 0; s < static_cast<int>(options.base.size()); ++s) {
      const BaseSetting& setting = options.base[static_cast<std::size_t>(s)];
      const bool weighted = options.selection == Selection::kWeights && AcceptsSampleWeights(setting.kind);
      const std::vector<int>& idx = weighted ? all : subset;
      std::vector<int> sub_labels;
      sub_labels.reserve(idx.size());
      for (int i : idx) sub_labels.push_back(data.labels[static_cast<std::size_t>(i)]);
      for (int t = 0; t < static_cast<int>(scaled.size()); ++t) {
        std::unique_ptr<BaseClassifier> clf;
        try {
          clf = TrainBaseClassifier(setting, weighted ? scaled[static_cast<std::size_t>(t)] : Rows(scaled[static_cast<std::size_t>(t)], idx),
                                    sub_labels, weighted ? std::span<const float>(w_all) : std::span<const float>(),
                                    k, options.seed + static_cast<std::uint64_t>(round) * 7919u + static_cast<std::uint64_t>(s));
        } catch (const Error&) {
          continue;  // this combination cannot be trained on this resample; the others compete
        }
        const std::vector<int> pred = clf->Predict(scaled[static_cast<std::size_t>(t)]);
        std::vector<bool> mistakes(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
          mistakes[static_cast<std::size_t>(i)] = pred[static_cast<std::size_t>(i)] != data.labels[static_cast<std::size_t>(i)];
        }
        // The rule: the weighted error on the whole training set. kOutOfBag: on the samples the resample
        // left out (a held-out estimate; a fit on every sample has none and keeps the whole-set error).
        double e = std::numeric_limits<double>::quiet_NaN();
        const bool held_out = options.error_on == ErrorMeasure::kOutOfBag && !weighted;
        if (held_out) e = WeightedError(w, mistakes, in_subset);  // NaN when the resample left nothing out
        const bool measured_out_of_bag = !std::isnan(e);
        if (!measured_out_of_bag) e = WeightedError(w, mistakes, {});
        if (std::isnan(e)) e = 1.0;
        if (e < best_error) {
          best_error = e;
          best.setting = s;
          best.feature_type = t;
          best.error = e;
          best.classifier = std::move(clf);
          best_wrong = std::move(mistakes);
          best_measured_on = measured_out_of_bag ? static_cast<int>(std::count(in_subset.begin(), in_subset.end(), false)) : n;
        }
      }
    }
    if (!best.classifier || best_error >= chance - 1e-12) {  // sums of equal weights land a hair under chance
      if (model.rounds.empty()) {
        throw Error(ErrorCode::kUnprocessable, "no base classifier and feature type beats chance ((K-1)/K) on this training set");
      }
      break;
    }
    bool perfect = best_error <= 0.0;
    if (perfect && options.error_on == ErrorMeasure::kOutOfBag && options.selection != Selection::kMaximum) {
      // No mistake on m held-out samples bounds the error by about 1/m, not 0: e is floored at half a sample's
      // share, and training goes on (this round changes no weight; the next one differs by its resample).
      best_error = 0.5 / best_measured_on;
      best.error = best_error;
      perfect = false;
    }
    best.alpha = options.learning_rate * SammeAlpha(best_error, k, options.update);
    model.rounds.push_back(best);
    if (perfect) {
      if (callback) callback(options.rounds, options.rounds);
      break;
    }
    ReweightSamples(w, best_wrong, best.alpha, options.update);
    if (callback && !callback(round + 1, options.rounds)) throw Error(ErrorCode::kConflict, "cancelled");
  }
  return model;
}

namespace {

std::vector<FeatureMatrix> ScaleFor(const EsammeModel& model, const std::vector<FeatureMatrix>& features) {
  if (features.size() != model.feature_types.size()) {
    throw Error(ErrorCode::kInvalidArgument, "one descriptor matrix per feature type of the model", "samples");
  }
  std::vector<FeatureMatrix> scaled;
  for (std::size_t t = 0; t < features.size(); ++t) {
    if (features[t].cols() != model.feature_dims[t] || features[t].rows() != features[0].rows()) {
      throw Error(ErrorCode::kInvalidArgument, "feature type '" + model.feature_types[t] + "' needs descriptors of length " +
                                                   std::to_string(model.feature_dims[t]), "samples");
    }
    CheckFinite(features[t], "samples");
    scaled.push_back(Apply(model.scaling[t], features[t]));
  }
  return scaled;
}

}  // namespace

std::vector<std::vector<int>> PredictRounds(const EsammeModel& model, const std::vector<FeatureMatrix>& features) {
  const auto scaled = ScaleFor(model, features);
  std::vector<std::vector<int>> out;
  for (const auto& r : model.rounds) out.push_back(r.classifier->Predict(scaled[static_cast<std::size_t>(r.feature_type)]));
  return out;
}

std::vector<EsammePrediction> PredictEsamme(const EsammeModel& model, const std::vector<FeatureMatrix>& features,
                                            int max_rounds) {
  const auto per_round = PredictRounds(model, features);
  const std::size_t n = features.empty() ? 0 : static_cast<std::size_t>(features[0].rows());
  const std::size_t k = model.class_names.size();
  const std::size_t used = max_rounds < 0 ? per_round.size() : std::min(per_round.size(), static_cast<std::size_t>(max_rounds));
  int unknown_index = -1;
  for (std::size_t c = 0; c < k; ++c) if (model.class_names[c] == kUnknownClass) unknown_index = static_cast<int>(c);
  std::vector<EsammePrediction> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> votes(k, 0.0);
    double total = 0.0;
    for (std::size_t r = 0; r < used; ++r) {
      votes[static_cast<std::size_t>(per_round[r][i])] += model.rounds[r].alpha;
      total += model.rounds[r].alpha;
    }
    if (total > 0) for (double& v : votes) v /= total;
    const auto best = std::max_element(votes.begin(), votes.end());  // ties: the lower class index
    out[i].label = static_cast<int>(best - votes.begin());
    if (model.unknown && unknown_index >= 0 && *best < model.unknown_min_share) out[i].label = unknown_index;
    out[i].distribution = std::move(votes);
  }
  return out;
}

}  // namespace anchordb::engine
