#pragma once
// E-SAMME (thesis 4.2.1, Algorithm 4): multi-class SAMME boosting whose every round trains every (base classifier
// setting x feature type) combination on a resample of the weighted training set and keeps the combination with the
// least weighted error on the whole training set.
//
// alpha_t = log((1 - e_t) / e_t) + log(K - 1) (eq. 4.9). Weight update, chosen by `WeightUpdate`:
//   kThesis  (eq. 4.10): correct samples x exp(-alpha), wrong ones x exp(alpha), then renormalised;
//   kSklearn (scikit-learn's SAMME, and Zhu et al. 2009): only wrong samples x exp(alpha), then renormalised.
// Eq. 4.10 moves the weights twice as far (the wrong/correct ratio grows by exp(2 alpha)): with K = 2 the learner
// just chosen ends at weighted error 1 - e, so its inverse tends to win the next round.
// Stopping: a round whose best combination has e >= (K - 1) / K ends training (that combination is discarded; in
// the first round Train throws). At e = 0 the round's combination is perfect on the weighted training set and
// further rounds cannot reweight anything: it is kept and training stops; its alpha is computed from e clamped to
// 1e-10 (about 23 + log(K-1), so it outvotes the earlier rounds) under kThesis, and is 1 under kSklearn (as
// scikit-learn does).
// Which error ranks the combinations and gives alpha (`ErrorMeasure`):
//   kWhole (default, the rule): the weighted error on the whole training set;
//   kOutOfBag: the weighted error on the training samples the round's resample left out (normalised by their
//     weight). A learner that interpolates its resample (an RBF SVM with a large gamma, a deep tree, 1-NN) has a
//     whole-set error that counts its own training samples as right, so under kWhole it wins rounds with an error
//     near or at 0, gets a huge alpha and outvotes everything (or ends training alone); out of bag it is judged on
//     samples it did not see. Fits on every sample (kWeights' weighted kinds) have no such samples and keep the
//     whole-set error, so kOutOfBag is meant for kRoulette or kMaximum. The weight update always uses the mistakes
//     on the whole training set. At e = 0 out of bag (no mistake on m unseen samples, an error bound of about 1/m
//     rather than proof of perfection) e is floored at 1/(2m) and training goes on (the round changes no weight, the
//     next differs by its resample); under kMaximum, whose next resample takes the same heaviest samples (only the
//     draw among equal weights differs), it stops as above.
// learning_rate (shrinkage, nu in (0, 1]) multiplies every alpha: alpha_t = nu * (log((1-e)/e) + log(K-1)).
// Features are standardised per feature type (mean 0, standard deviation 1 over the training set; a constant
// dimension is left at 0) before the base classifiers see them; the model keeps the scaling.
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "engine/classification/base_classifiers.h"

namespace anchordb::engine {

// How a round's base classifiers get the weighted training set (thesis 4.2.1):
//   kMaximum:  the Z = z_f * n samples of greatest weight, each once; equal weights in a seeded random order (on
//              class-sorted data with equal weights a lower-index-first rule would take the first classes only);
//   kRoulette: Z draws with replacement, each sample with probability w_i (seeded);
//   kWeights:  every sample with its weight for the kinds that accept weights (DTrees), roulette for the others.
enum class Selection { kMaximum, kRoulette, kWeights };
enum class WeightUpdate { kThesis, kSklearn };
enum class ErrorMeasure { kWhole, kOutOfBag };

// "maximum" | "roulette" | "weights"; "thesis" | "sklearn". Parse* throw Error(kInvalidArgument).
const char* SelectionName(Selection s);
Selection ParseSelection(const std::string& name);
const char* WeightUpdateName(WeightUpdate u);
WeightUpdate ParseWeightUpdate(const std::string& name);
// "whole" | "out_of_bag".
const char* ErrorMeasureName(ErrorMeasure m);
ErrorMeasure ParseErrorMeasure(const std::string& name);

// The name of the optional rejection class.
inline constexpr const char* kUnknownClass = "unknown";

// A labelled training set: one n x d_t matrix per feature type (every type has the same n rows, in sample order).
struct TrainingSet {
  std::vector<std::string> class_names;    // K names, distinct
  std::vector<std::string> feature_types;  // T names, distinct
  std::vector<FeatureMatrix> features;     // T matrices, n rows each
  std::vector<int> labels;                 // n labels in [0, K)
};

struct EsammeOptions {
  std::vector<BaseSetting> base;  // the classifier settings (at least one)
  int rounds = 50;                // T, in [1, 1000]
  Selection selection = Selection::kMaximum;
  double sample_factor = 0.6;     // z_f in (0, 1]: Z = max(K, round(z_f * n)) samples per round
  WeightUpdate update = WeightUpdate::kThesis;
  ErrorMeasure error_on = ErrorMeasure::kWhole;
  double learning_rate = 1.0;     // nu in (0, 1], multiplies alpha
  std::uint64_t seed = 1;
  // With `unknown`, predictions whose winning share of the summed alpha is below unknown_min_share are "unknown"
  // (the class must then be among the class names; samples may be labelled with it as negative examples).
  bool unknown = false;
  double unknown_min_share = 0.5;
};

// Throws Error(kInvalidArgument / kUnprocessable, field) for options out of range or a training set that cannot be
// trained: no samples, rows differing between feature types, NaN/inf features, a label out of range, fewer than two
// classes with samples, `unknown` without an "unknown" class.
void ValidateTraining(const TrainingSet& data, const EsammeOptions& options);

// One chosen round of the additive model.
struct EsammeRound {
  int setting = 0;         // index into the model's settings
  int feature_type = 0;    // index into the model's feature types
  double error = 0.0;      // weighted training error e_t when chosen
  double alpha = 0.0;      // classifier weight
  std::shared_ptr<const BaseClassifier> classifier;
};

// Per-feature-type standardisation kept with the model.
struct FeatureScaling {
  Eigen::VectorXf mean;
  Eigen::VectorXf inv_std;  // 0 for a constant dimension
};

struct EsammeModel {
  std::vector<std::string> class_names;
  std::vector<std::string> feature_types;
  std::vector<int> feature_dims;  // descriptor length per feature type
  std::vector<FeatureScaling> scaling;
  std::vector<BaseSetting> settings;
  std::vector<EsammeRound> rounds;
  bool unknown = false;
  double unknown_min_share = 0.5;
};

// The prediction of a sample: the class and the normalised vote shares (sum of alpha per class / sum of alpha).
struct EsammePrediction {
  int label = 0;
  std::vector<double> distribution;
};

// Called after every round with (rounds done, rounds asked); return false to cancel (Train then throws
// Error(kConflict, "cancelled")).
using RoundCallback = std::function<bool(int done, int total)>;

// The maximum selection of a round: the indices (ascending) of the min(z, n) samples of greatest weight; among equal
// weights the order is a random permutation drawn from `rng` (deterministic for a given seed and call sequence).
std::vector<int> MaximumSelection(const std::vector<double>& weights, int z, std::mt19937_64& rng);

// alpha of a round with weighted error e among K classes (eq. 4.9; e = 0 as described at the top).
double SammeAlpha(double error, int num_classes, WeightUpdate update);
// One weight update (eq. 4.10 or scikit-learn's) followed by renormalisation to sum 1.
void ReweightSamples(std::vector<double>& weights, const std::vector<bool>& wrong, double alpha, WeightUpdate update);

// Trains E-SAMME. Throws as ValidateTraining, and Error(kUnprocessable) when no combination beats chance in the
// first round.
EsammeModel TrainEsamme(const TrainingSet& data, const EsammeOptions& options, const RoundCallback& callback = {});

// Predicts samples given as one matrix per model feature type (same rows). `max_rounds` < 0 uses every round.
// Throws Error(kInvalidArgument) when the matrices do not fit the model.
std::vector<EsammePrediction> PredictEsamme(const EsammeModel& model, const std::vector<FeatureMatrix>& features,
                                            int max_rounds = -1);

// Every round's class prediction per sample (rounds x n), for staged errors.
std::vector<std::vector<int>> PredictRounds(const EsammeModel& model, const std::vector<FeatureMatrix>& features);

// The model as a versioned binary blob (magic "ESAM", version 2, version 1 still read; base models as OpenCV FileStorage text) and back.
// DecodeEsamme throws Error(kUnprocessable) on a damaged or foreign blob.
std::string EncodeEsamme(const EsammeModel& model);
EsammeModel DecodeEsamme(const std::string& blob);

}  // namespace anchordb::engine
