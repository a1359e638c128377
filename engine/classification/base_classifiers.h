#pragma once
// Base classifiers of E-SAMME (thesis 4.2): OpenCV ml's SVM (RBF kernel), DTrees, ANN_MLP and KNearest behind an
// OpenCV-free interface. A setting is one configuration of one kind; E-SAMME gets a list of them.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace anchordb::engine {

// Samples as rows (n x d), float like OpenCV ml's training data.
using FeatureMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

enum class BaseKind { kSvm, kDTree, kMlp, kKnn };

// "svm" | "dtree" | "mlp" | "knn"; ParseBaseKind throws Error(kInvalidArgument) on anything else.
const char* BaseKindName(BaseKind kind);
BaseKind ParseBaseKind(const std::string& name);

// One configuration of one base classifier kind. Only the fields of `kind` are used.
struct BaseSetting {
  BaseKind kind = BaseKind::kDTree;
  double svm_c = 1.0;               // SVM soft margin C (> 0)
  double svm_gamma = 0.1;           // RBF kernel gamma (> 0), on standardised features
  // When true the kernel's gamma is svm_gamma / d, d the descriptor length of the feature type it is trained on:
  // exp(-svm_gamma * |x - y|^2 / d), the same width relative to the mean squared distance of standardised samples
  // (2 d) for every descriptor length (scikit-learn's gamma = "scale" at svm_gamma 1).
  bool svm_gamma_per_dim = false;
  int tree_max_depth = 1;           // 1 = decision stump
  int tree_min_samples = 2;         // fewest samples a node needs to be split
  std::vector<int> mlp_hidden{16};  // neurons per hidden layer (1-3 layers)
  int mlp_iterations = 200;         // RPROP epochs
  int knn_k = 3;                    // neighbours voting
  // A stable short name, e.g. "svm(C=1,gamma=0.1)" ("gamma=1/d" per dimension), "dtree(depth=1,min=2)", "mlp(16)", "knn(k=3)".
  std::string Name() const;
};

// Throws Error(kInvalidArgument, field) when a value is out of its range.
void ValidateBaseSetting(const BaseSetting& setting, const std::string& field);

// The SVM grid of every (C, gamma) pair (gamma per dimension when `gamma_per_dim`).
std::vector<BaseSetting> SvmGrid(const std::vector<double>& cs, const std::vector<double>& gammas,
                                 bool gamma_per_dim = false);
// A default base set: stumps, trees of depth 3 and 6, an SVM grid (C {1, 10} x gamma {0.1, 1} per dimension), two
// MLPs, KNN k=1 and k=5.
std::vector<BaseSetting> DefaultBaseSet();

// A trained base classifier: predicts class indices in [0, K).
class BaseClassifier {
 public:
  virtual ~BaseClassifier() = default;
  virtual std::vector<int> Predict(const FeatureMatrix& rows) const = 0;
  // The model as text (OpenCV FileStorage YAML; "constant <k>" for a one-class training set).
  virtual std::string Serialize() const = 0;
};

// Trains one base classifier on `rows` with labels in [0, num_classes). `weights` (empty or one per row) is used
// by the kinds that accept sample weights (DTrees); the others ignore it. A training set with one class gives a
// constant classifier. `seed` seeds OpenCV's RNG (MLP weight initialisation). Throws Error(kUnprocessable) when
// OpenCV refuses the data.
std::unique_ptr<BaseClassifier> TrainBaseClassifier(const BaseSetting& setting, const FeatureMatrix& rows,
                                                    const std::vector<int>& labels, std::span<const float> weights,
                                                    int num_classes, std::uint64_t seed);
// True for the kinds whose training honours sample weights.
bool AcceptsSampleWeights(BaseKind kind);

// Rebuilds a classifier from Serialize()'s text. Throws Error(kUnprocessable) on text OpenCV cannot read.
std::unique_ptr<BaseClassifier> LoadBaseClassifier(BaseKind kind, const std::string& text, int num_classes);

}  // namespace anchordb::engine
