#include "engine/classification/base_classifiers.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/ml.hpp>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

std::string Num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

cv::Mat AsMat(const FeatureMatrix& rows) {
  // A view on the Eigen storage (row-major float), no copy.
  return cv::Mat(static_cast<int>(rows.rows()), static_cast<int>(rows.cols()), CV_32F,
                 const_cast<float*>(rows.data()));
}

class ConstantClassifier final : public BaseClassifier {
 public:
  explicit ConstantClassifier(int label) : label_(label) {}
  std::vector<int> Predict(const FeatureMatrix& rows) const override {
    return std::vector<int>(static_cast<std::size_t>(rows.rows()), label_);
  }
  std::string Serialize() const override { return "constant " + std::to_string(label_); }

 private:
  int label_;
};

std::string WriteModel(const cv::Ptr<cv::ml::StatModel>& model) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "model" << "{";
  model->write(fs);
  fs << "}";
  return fs.releaseAndGetString();
}

// A trained OpenCV StatModel; `kind` decides how its outputs become class indices.
class OpenCvClassifier final : public BaseClassifier {
 public:
  OpenCvClassifier(BaseKind kind, cv::Ptr<cv::ml::StatModel> model, int num_classes, int knn_k)
      : kind_(kind), model_(std::move(model)), num_classes_(num_classes), knn_k_(knn_k) {}

  std::vector<int> Predict(const FeatureMatrix& rows) const override {
    std::vector<int> out(static_cast<std::size_t>(rows.rows()), 0);
    if (rows.rows() == 0) return out;
    const cv::Mat samples = AsMat(rows);
    cv::Mat result;
    if (kind_ == BaseKind::kKnn) {
      auto knn = model_.staticCast<cv::ml::KNearest>();
      knn->findNearest(samples, knn_k_, result);
    } else {
      model_->predict(samples, result);
    }
    for (int i = 0; i < samples.rows; ++i) {
      int label = 0;
      if (kind_ == BaseKind::kMlp) {
        cv::Point max_at;
        cv::minMaxLoc(result.row(i), nullptr, nullptr, nullptr, &max_at);
        label = max_at.x;
      } else {
        label = static_cast<int>(std::lround(result.at<float>(i, 0)));
      }
      out[static_cast<std::size_t>(i)] = std::clamp(label, 0, num_classes_ - 1);
    }
    return out;
  }
  std::string Serialize() const override { return WriteModel(model_); }

 private:
  BaseKind kind_;
  cv::Ptr<cv::ml::StatModel> model_;
  int num_classes_;
  int knn_k_;
};

cv::Ptr<cv::ml::StatModel> MakeModel(const BaseSetting& s, int dims, int num_classes) {
  switch (s.kind) {
    case BaseKind::kSvm: {
      auto svm = cv::ml::SVM::create();
      svm->setType(cv::ml::SVM::C_SVC);
      svm->setKernel(cv::ml::SVM::RBF);
      svm->setC(s.svm_c);
      svm->setGamma(s.svm_gamma_per_dim ? s.svm_gamma / std::max(1, dims) : s.svm_gamma);
      svm->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 1000, 1e-3));
      return svm;
    }
    case BaseKind::kDTree: {
      auto tree = cv::ml::DTrees::create();
      tree->setMaxDepth(s.tree_max_depth);
      tree->setMinSampleCount(s.tree_min_samples);
      tree->setCVFolds(0);
      tree->setUseSurrogates(false);
      tree->setUse1SERule(false);
      tree->setTruncatePrunedTree(false);
      tree->setMaxCategories(std::max(2, num_classes));
      return tree;
    }
    case BaseKind::kMlp: {
      auto mlp = cv::ml::ANN_MLP::create();
      cv::Mat layers(static_cast<int>(s.mlp_hidden.size()) + 2, 1, CV_32S);
      layers.at<int>(0) = dims;
      for (std::size_t i = 0; i < s.mlp_hidden.size(); ++i) layers.at<int>(static_cast<int>(i) + 1) = s.mlp_hidden[i];
      layers.at<int>(layers.rows - 1) = num_classes;
      mlp->setLayerSizes(layers);
      mlp->setActivationFunction(cv::ml::ANN_MLP::SIGMOID_SYM, 1.0, 1.0);
      mlp->setTrainMethod(cv::ml::ANN_MLP::RPROP);
      mlp->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, s.mlp_iterations, 1e-4));
      return mlp;
    }
    case BaseKind::kKnn: {
      auto knn = cv::ml::KNearest::create();
      knn->setDefaultK(s.knn_k);
      knn->setIsClassifier(true);
      return knn;
    }
  }
  return {};
}

}  // namespace

const char* BaseKindName(BaseKind kind) {
  switch (kind) {
    case BaseKind::kSvm: return "svm";
    case BaseKind::kDTree: return "dtree";
    case BaseKind::kMlp: return "mlp";
    case BaseKind::kKnn: return "knn";
  }
  return "?";
}

BaseKind ParseBaseKind(const std::string& name) {
  for (BaseKind k : {BaseKind::kSvm, BaseKind::kDTree, BaseKind::kMlp, BaseKind::kKnn}) {
    if (name == BaseKindName(k)) return k;
  }
  throw Error(ErrorCode::kInvalidArgument, "unknown base classifier kind '" + name + "' (svm, dtree, mlp, knn)",
              "kind");
}

std::string BaseSetting::Name() const {
  switch (kind) {
    case BaseKind::kSvm: return "svm(C=" + Num(svm_c) + ",gamma=" + Num(svm_gamma) + (svm_gamma_per_dim ? "/d" : "") + ")";
    case BaseKind::kDTree: return "dtree(depth=" + std::to_string(tree_max_depth) + ",min=" +
                                  std::to_string(tree_min_samples) + ")";
    case BaseKind::kMlp: {
      std::string name = "mlp(";
      for (std::size_t i = 0; i < mlp_hidden.size(); ++i) name += (i ? "x" : "") + std::to_string(mlp_hidden[i]);
      return name + ",it=" + std::to_string(mlp_iterations) + ")";
    }
    case BaseKind::kKnn: return "knn(k=" + std::to_string(knn_k) + ")";
  }
  return "?";
}

void ValidateBaseSetting(const BaseSetting& s, const std::string& field) {
  auto bad = [&](const std::string& what) { throw Error(ErrorCode::kInvalidArgument, what, field); };
  switch (s.kind) {
    case BaseKind::kSvm:
      if (!(s.svm_c > 0 && s.svm_c < 1e9 && s.svm_gamma > 0 && s.svm_gamma < 1e9)) bad("svm C and gamma must be in (0, 1e9)");
      break;
    case BaseKind::kDTree:
      if (s.tree_max_depth < 1 || s.tree_max_depth > 25) bad("dtree depth must be in [1, 25]");
      if (s.tree_min_samples < 1 || s.tree_min_samples > 100000) bad("dtree min_samples must be in [1, 100000]");
      break;
    case BaseKind::kMlp:
      if (s.mlp_hidden.empty() || s.mlp_hidden.size() > 3) bad("mlp needs 1 to 3 hidden layers");
      for (int h : s.mlp_hidden) if (h < 1 || h > 1024) bad("mlp hidden layer sizes must be in [1, 1024]");
      if (s.mlp_iterations < 1 || s.mlp_iterations > 10000) bad("mlp iterations must be in [1, 10000]");
      break;
    case BaseKind::kKnn:
      if (s.knn_k < 1 || s.knn_k > 100) bad("knn k must be in [1, 100]");
      break;
  }
}

std::vector<BaseSetting> SvmGrid(const std::vector<double>& cs, const std::vector<double>& gammas, bool gamma_per_dim) {
  std::vector<BaseSetting> grid;
  for (double c : cs) {
    for (double g : gammas) {
      BaseSetting s;
      s.kind = BaseKind::kSvm;
      s.svm_c = c;
      s.svm_gamma = g;
      s.svm_gamma_per_dim = gamma_per_dim;
      grid.push_back(s);
    }
  }
  return grid;
}

std::vector<BaseSetting> DefaultBaseSet() {
  std::vector<BaseSetting> set;
  for (int depth : {1, 3, 6}) {
    BaseSetting s;
    s.kind = BaseKind::kDTree;
    s.tree_max_depth = depth;
    set.push_back(s);
  }
  // gamma per dimension: a fixed gamma is a kernel width that depends on the descriptor length (the mean squared
  // distance of standardised samples is 2 d): {0.01, 0.1} was nearly linear on 4 dimensions and narrow on 64.
  for (const auto& s : SvmGrid({1.0, 10.0}, {0.1, 1.0}, true)) set.push_back(s);
  for (int hidden : {16, 48}) {
    BaseSetting s;
    s.kind = BaseKind::kMlp;
    s.mlp_hidden = {hidden};
    set.push_back(s);
  }
  for (int k : {1, 5}) {
    BaseSetting s;
    s.kind = BaseKind::kKnn;
    s.knn_k = k;
    set.push_back(s);
  }
  return set;
}

bool AcceptsSampleWeights(BaseKind kind) { return kind == BaseKind::kDTree; }

std::unique_ptr<BaseClassifier> TrainBaseClassifier(const BaseSetting& setting, const FeatureMatrix& rows,
                                                    const std::vector<int>& labels, std::span<const float> weights,
                                                    int num_classes, std::uint64_t seed) {
  if (rows.rows() == 0 || static_cast<std::size_t>(rows.rows()) != labels.size()) {
    throw Error(ErrorCode::kUnprocessable, "a base classifier needs one label per sample and at least one sample");
  }
  const int first = labels.front();
  if (std::all_of(labels.begin(), labels.end(), [&](int l) { return l == first; })) {
    return std::make_unique<ConstantClassifier>(first);
  }
  const cv::Mat samples = AsMat(rows);
  cv::Mat responses;
  if (setting.kind == BaseKind::kMlp) {
    responses = cv::Mat::zeros(samples.rows, num_classes, CV_32F);
    for (int i = 0; i < samples.rows; ++i) responses.at<float>(i, labels[static_cast<std::size_t>(i)]) = 1.0f;
  } else if (setting.kind == BaseKind::kKnn) {
    cv::Mat(labels, true).convertTo(responses, CV_32F);
  } else {
    responses = cv::Mat(labels, true).reshape(1, samples.rows);
  }
  cv::Mat sample_weights;
  if (AcceptsSampleWeights(setting.kind) && !weights.empty()) {
    sample_weights = cv::Mat(1, static_cast<int>(weights.size()), CV_32F, const_cast<float*>(weights.data())).clone();
  }
  cv::Mat var_type;
  if (setting.kind == BaseKind::kDTree || setting.kind == BaseKind::kSvm) {
    var_type = cv::Mat(1, samples.cols + 1, CV_8U, cv::Scalar(cv::ml::VAR_ORDERED));
    var_type.at<uchar>(0, samples.cols) = cv::ml::VAR_CATEGORICAL;
  }
  try {
    cv::setRNGSeed(static_cast<int>(seed & 0x7fffffff));
    auto data = cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses, cv::noArray(), cv::noArray(),
                                          sample_weights, var_type);
    auto model = MakeModel(setting, samples.cols, num_classes);
    if (!model->train(data)) throw Error(ErrorCode::kUnprocessable, "OpenCV could not train " + setting.Name());
    return std::make_unique<OpenCvClassifier>(setting.kind, model, num_classes, setting.knn_k);
  } catch (const cv::Exception& e) {
    throw Error(ErrorCode::kUnprocessable, "OpenCV could not train " + setting.Name() + ": " + e.err);
  }
}

std::unique_ptr<BaseClassifier> LoadBaseClassifier(BaseKind kind, const std::string& text, int num_classes) {
  if (text.rfind("constant ", 0) == 0) {
    int label = -1;
    try {
      label = std::stoi(text.substr(9));
    } catch (const std::exception&) {
    }
    if (label < 0 || label >= num_classes) throw Error(ErrorCode::kUnprocessable, "bad constant classifier");
    return std::make_unique<ConstantClassifier>(label);
  }
  try {
    cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    const cv::FileNode node = fs["model"];
    if (node.empty()) throw Error(ErrorCode::kUnprocessable, "base model text has no 'model' node");
    BaseSetting setting;
    setting.kind = kind;
    cv::Ptr<cv::ml::StatModel> model = MakeModel(setting, 1, std::max(num_classes, 2));
    model->read(node);
    if (!model->isTrained()) throw Error(ErrorCode::kUnprocessable, "base model text did not load a trained model");
    int k = 1;
    if (kind == BaseKind::kKnn) k = model.staticCast<cv::ml::KNearest>()->getDefaultK();
    return std::make_unique<OpenCvClassifier>(kind, model, num_classes, k);
  } catch (const cv::Exception& e) {
    throw Error(ErrorCode::kUnprocessable, std::string("OpenCV could not read a base model: ") + e.err);
  }
}

}  // namespace anchordb::engine
