#pragma once
// k-fold cross-validation of E-SAMME (thesis 4.2.2, 4.3.3): train and test error after every round, the confusion
// matrix of the final models, and which classifier kinds, settings and feature types the rounds chose (figures 4.8,
// 4.13, 4.15).
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "engine/classification/esamme.h"

namespace anchordb::engine {

// The fold (0..folds-1) of every sample: per class, the samples in a seeded random order dealt round-robin, so every
// fold holds about the same share of each class. Throws Error(kInvalidArgument) unless 2 <= folds <= n.
std::vector<int> StratifiedFolds(const std::vector<int>& labels, int folds, std::uint64_t seed);

// The rows `indices` of a training set (same classes and feature types).
TrainingSet SubsetOf(const TrainingSet& data, const std::vector<int>& indices);

struct CrossValidationReport {
  int folds = 0;
  std::vector<double> train_error_per_round;  // [r] = mean over folds after r+1 rounds (a fold that stopped
  std::vector<double> test_error_per_round;   //   early keeps its last value)
  std::vector<double> test_error_worst_fold_per_round;
  std::vector<std::vector<int>> confusion;  // K x K: rows the true class, columns the prediction (test samples)
  double test_error = 0.0;                  // of the final models over every test sample
  std::vector<int> rounds_per_fold;
  // Shares among every chosen round of every fold (each list sums to 1), in first-seen order.
  std::vector<std::pair<std::string, double>> kind_share;
  std::vector<std::pair<std::string, double>> setting_share;
  std::vector<std::pair<std::string, double>> feature_share;
};

// Cross-validates with the given fold of every sample (e.g. StratifiedFolds, or folds read from a file). Throws
// Error(kInvalidArgument) when `fold_of_sample` does not fit (size, a fold without samples, fewer than two folds),
// and as TrainEsamme for each fold. `callback(done, total)` counts boosting rounds over all folds (a fold that stops early jumps ahead); false
// cancels (Error kConflict).
CrossValidationReport CrossValidate(const TrainingSet& data, const EsammeOptions& options,
                                    const std::vector<int>& fold_of_sample, const RoundCallback& callback = {});

// As CrossValidate, with the features of fold f's training and test samples taken from `data_for_fold(f)` (the same
// samples, labels and classes for every f): for features that are themselves learned from the training samples, e.g.
// bags of words over a codebook built from the training fold only. Each fold's set is validated as CrossValidate's.
CrossValidationReport CrossValidatePerFold(const std::function<TrainingSet(int fold)>& data_for_fold,
                                           const EsammeOptions& options, const std::vector<int>& fold_of_sample,
                                           const RoundCallback& callback = {});

}  // namespace anchordb::engine
