#pragma once
// The stored documents of an E-SAMME classifier (storage/document_codec.h): its training options (with the model and
// in the training job's request), its training report (with the model) and the training job's result. Records of
// storage's own: kinds, selections and error measures are the engine's names as text, mapped in services.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anchordb::storage {

struct ClassifierBaseSettingRecord {
  std::string kind;  // "svm" | "dtree" | "mlp" | "knn"
  double svm_c = 0.0;
  double svm_gamma = 0.0;
  bool svm_gamma_per_dim = false;
  int tree_max_depth = 0;
  int tree_min_samples = 0;
  std::vector<int> mlp_hidden;
  int mlp_iterations = 0;
  int knn_k = 0;
};

struct ClassifierOptionsRecord {
  std::string name;
  std::vector<ClassifierBaseSettingRecord> base;  // empty: the default base set
  int rounds = 0;
  std::string selection;
  double sample_factor = 0.0;
  int folds = 0;
  std::uint64_t seed = 0;
  std::string update;
  std::string error_on;
  double learning_rate = 0.0;
  bool unknown = false;
  double unknown_min_share = 0.0;
};

using NamedCounts = std::vector<std::pair<std::string, std::int64_t>>;
using NamedShares = std::vector<std::pair<std::string, double>>;

// The training job's request: the options, what the samples are (not the samples: they stay in memory, under
// `staging`, until the job runs).
struct ClassifierTrainingRequestRecord {
  ClassifierOptionsRecord options;
  std::int64_t sample_count = 0;
  NamedCounts class_counts;  // in class order
  NamedCounts feature_dims;  // descriptor length per feature type
  std::int64_t staging = 0;
};

struct ClassifierRoundRecord {
  std::string setting;  // the base setting's name
  std::string feature_type;
  double error = 0.0;
  double alpha = 0.0;
};

struct ClassifierCrossValidationRecord {
  std::int64_t folds = 0;
  double test_error = 0.0;
  std::vector<double> train_error_per_round;
  std::vector<double> test_error_per_round;
  std::vector<double> test_error_worst_fold_per_round;
  std::vector<std::vector<std::int64_t>> confusion;  // rows the true class, columns the prediction
  std::vector<std::int64_t> rounds_per_fold;
  NamedShares kind_share;
  NamedShares setting_share;
  NamedShares feature_share;
};

struct ClassifierReportRecord {
  std::vector<std::string> classes;
  std::vector<std::string> feature_types;
  std::int64_t samples = 0;
  std::vector<ClassifierRoundRecord> rounds;
  double train_seconds = 0.0;
  std::optional<ClassifierCrossValidationRecord> cross_validation;
};

struct ClassifierTrainingResultRecord {
  std::string name;
  std::int64_t rounds = 0;
  double train_seconds = 0.0;
  std::optional<double> test_error;  // with cross-validation
};

// Decoders throw Error(kInternal) naming `what` for bytes that are not such a document (document_codec.h).
std::string EncodeClassifierOptions(const ClassifierOptionsRecord& options);
ClassifierOptionsRecord DecodeClassifierOptions(std::string_view stored, const std::string& what);
std::string EncodeClassifierReport(const ClassifierReportRecord& report);
ClassifierReportRecord DecodeClassifierReport(std::string_view stored, const std::string& what);
std::string EncodeClassifierTrainingRequest(const ClassifierTrainingRequestRecord& request);
ClassifierTrainingRequestRecord DecodeClassifierTrainingRequest(std::string_view stored, const std::string& what);
std::string EncodeClassifierTrainingResult(const ClassifierTrainingResultRecord& result);
ClassifierTrainingResultRecord DecodeClassifierTrainingResult(std::string_view stored, const std::string& what);

}  // namespace anchordb::storage
