#include "engine/classification/cross_validation.h"

#include <algorithm>
#include <map>
#include <random>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

void AddShare(std::vector<std::pair<std::string, double>>& shares, const std::string& name) {
  for (auto& [key, count] : shares) {
    if (key == name) {
      count += 1.0;
      return;
    }
  }
  shares.emplace_back(name, 1.0);
}

void Normalise(std::vector<std::pair<std::string, double>>& shares) {
  double total = 0.0;
  for (const auto& s : shares) total += s.second;
  if (total > 0) for (auto& s : shares) s.second /= total;
}

// Error after each of `rounds` rounds (staged votes), given every round's predictions.
std::vector<double> StagedErrors(const EsammeModel& model, const std::vector<std::vector<int>>& per_round,
                                 const std::vector<int>& labels, int rounds, std::vector<int>* final_pred) {
  const std::size_t n = labels.size();
  const std::size_t k = model.class_names.size();
  std::vector<std::vector<double>> votes(n, std::vector<double>(k, 0.0));
  std::vector<double> errors;
  std::vector<int> pred(n, 0);
  for (int r = 0; r < rounds; ++r) {
    if (r < static_cast<int>(per_round.size())) {
      for (std::size_t i = 0; i < n; ++i) votes[i][static_cast<std::size_t>(per_round[static_cast<std::size_t>(r)][i])] +=
          model.rounds[static_cast<std::size_t>(r)].alpha;
    }
    int wrong = 0;
    for (std::size_t i = 0; i < n; ++i) {
      pred[i] = static_cast<int>(std::max_element(votes[i].begin(), votes[i].end()) - votes[i].begin());
      if (pred[i] != labels[i]) ++wrong;
    }
    errors.push_back(n ? static_cast<double>(wrong) / static_cast<double>(n) : 0.0);
  }
  if (final_pred) *final_pred = pred;
  return errors;
}

}  // namespace

std::vector<int> StratifiedFolds(const std::vector<int>& labels, int folds, std::uint64_t seed) {
  if (folds < 2 || static_cast<std::size_t>(folds) > labels.size()) {
    throw Error(ErrorCode::kInvalidArgument, "folds must be in [2, number of samples]", "folds");
  }
  std::map<int, std::vector<int>> by_class;
  for (std::size_t i = 0; i < labels.size(); ++i) by_class[labels[i]].push_back(static_cast<int>(i));
  std::mt19937_64 rng(seed);
  std::vector<int> fold(labels.size(), 0);
  int next = 0;  // continues across classes so that small classes do not all land in fold 0
  for (auto& [label, members] : by_class) {
    for (std::size_t i = members.size(); i > 1; --i) std::swap(members[i - 1], members[rng() % i]);  // portable shuffle
    for (int m : members) {
      fold[static_cast<std::size_t>(m)] = next;
      next = (next + 1) % folds;
    }
  }
  return fold;
}

TrainingSet SubsetOf(const TrainingSet& data, const std::vector<int>& indices) {
  TrainingSet out;
  out.class_names = data.class_names;
  out.feature_types = data.feature_types;
  for (const auto& x : data.features) {
    FeatureMatrix rows(static_cast<Eigen::Index>(indices.size()), x.cols());
    for (std::size_t i = 0; i < indices.size(); ++i) rows.row(static_cast<Eigen::Index>(i)) = x.row(indices[i]);
    out.features.push_back(std::move(rows));
  }
  for (int i : indices) out.labels.push_back(data.labels[static_cast<std::size_t>(i)]);
  return out;
}

CrossValidationReport CrossValidate(const TrainingSet& data, const EsammeOptions& options,
                                    const std::vector<int>& fold_of_sample, const RoundCallback& callback) {
  ValidateTraining(data, options);
  return CrossValidatePerFold([&](int) -> const TrainingSet& { return data; }, options, fold_of_sample, callback);
}

CrossValidationReport CrossValidatePerFold(const std::function<TrainingSet(int fold)>& data_for_fold,
                                           const EsammeOptions& options, const std::vector<int>& fold_of_sample,
                                           const RoundCallback& callback) {
  if (fold_of_sample.empty()) throw Error(ErrorCode::kInvalidArgument, "one fold per sample", "folds");
  const TrainingSet first = data_for_fold(0);
  ValidateTraining(first, options);
  if (fold_of_sample.size() != first.labels.size()) {
    throw Error(ErrorCode::kInvalidArgument, "one fold per sample", "folds");
  }
  const int folds = fold_of_sample.empty() ? 0 : *std::max_element(fold_of_sample.begin(), fold_of_sample.end()) + 1;
  if (folds < 2 || *std::min_element(fold_of_sample.begin(), fold_of_sample.end()) < 0) {
    throw Error(ErrorCode::kInvalidArgument, "at least two folds, numbered from 0", "folds");
  }
  const std::size_t k = first.class_names.size();
  CrossValidationReport report;
  report.folds = folds;
  report.confusion.assign(k, std::vector<int>(k, 0));
  report.train_error_per_round.assign(static_cast<std::size_t>(options.rounds), 0.0);
  report.test_error_per_round.assign(static_cast<std::size_t>(options.rounds), 0.0);
  report.test_error_worst_fold_per_round.assign(static_cast<std::size_t>(options.rounds), 0.0);
  int wrong = 0, tested = 0;
  for (int f = 0; f < folds; ++f) {
    const TrainingSet data = f == 0 ? first : data_for_fold(f);
    if (data.labels != first.labels || data.class_names != first.class_names) {
      throw Error(ErrorCode::kInvalidArgument, "every fold's set has the same samples and classes", "folds");
    }
    ValidateTraining(data, options);
    std::vector<int> train_idx, test_idx;
    for (std::size_t i = 0; i < fold_of_sample.size(); ++i) {
      (fold_of_sample[i] == f ? test_idx : train_idx).push_back(static_cast<int>(i));
    }
    if (test_idx.empty() || train_idx.empty()) {
      throw Error(ErrorCode::kInvalidArgument, "fold " + std::to_string(f) + " has no samples", "folds");
    }
    const TrainingSet train = SubsetOf(data, train_idx);
    const TrainingSet test = SubsetOf(data, test_idx);
    EsammeOptions fold_options = options;
    fold_options.seed = options.seed + static_cast<std::uint64_t>(f) * 1000003u;
    const int total = folds * options.rounds;
    const EsammeModel model = TrainEsamme(train, fold_options, [&](int done, int) {
      return !callback || callback(f * options.rounds + done, total);
    });
    report.rounds_per_fold.push_back(static_cast<int>(model.rounds.size()));
    const auto train_err = StagedErrors(model, PredictRounds(model, train.features), train.labels, options.rounds, nullptr);
    std::vector<int> final_pred;
    const auto test_err = StagedErrors(model, PredictRounds(model, test.features), test.labels, options.rounds, &final_pred);
    for (std::size_t r = 0; r < test_err.size(); ++r) {
      report.train_error_per_round[r] += train_err[r] / folds;
      report.test_error_per_round[r] += test_err[r] / folds;
      report.test_error_worst_fold_per_round[r] = std::max(report.test_error_worst_fold_per_round[r], test_err[r]);
    }
    // The final prediction with the model's own rule (unknown threshold included).
    const auto predictions = PredictEsamme(model, test.features);
    for (std::size_t i = 0; i < predictions.size(); ++i) {
      const int truth = test.labels[i];
      const int pred = predictions[i].label;
      ++report.confusion[static_cast<std::size_t>(truth)][static_cast<std::size_t>(pred)];
      if (pred != truth) ++wrong;
      ++tested;
    }
    for (const auto& round : model.rounds) {
      const BaseSetting& s = model.settings[static_cast<std::size_t>(round.setting)];
      AddShare(report.kind_share, BaseKindName(s.kind));
      AddShare(report.setting_share, s.Name());
      AddShare(report.feature_share, model.feature_types[static_cast<std::size_t>(round.feature_type)]);
    }
  }
  report.test_error = tested ? static_cast<double>(wrong) / tested : 0.0;
  Normalise(report.kind_share);
  Normalise(report.setting_share);
  Normalise(report.feature_share);
  return report;
}

}  // namespace anchordb::engine
