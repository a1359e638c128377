// E-SAMME on a data set written by tests/eval/esamme_sklearn.py (X.csv, y.csv, folds.csv in one folder): the
// cross-validated accuracy on those folds and the training time, as one JSON line.
//   anchordb_eval_esamme --data DIR --config stumps|full|reduced [--rounds 50] [--update thesis|sklearn]
//                        [--selection weights|maximum|roulette] [--sample_factor 0.6] [--seed 1]
//                        [--error_on whole|out_of_bag] [--learning_rate 1]
// full: DefaultBaseSet() (stumps, trees of depth 3 and 6, SVM RBF C {1,10} x gamma {0.1,1}/d, MLP 16 and 48, KNN 1
// and 5); reduced: the same less depth 6 and 1-NN. Defaults: sklearn update, weighted fits, whole-set error.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/classification/cross_validation.h"
#include "schema/error.h"

using namespace anchordb;
using namespace anchordb::engine;

namespace {

std::vector<std::vector<double>> ReadCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, config = "stumps";
  EsammeOptions options;
  options.update = WeightUpdate::kSklearn;
  options.selection = Selection::kWeights;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--data") dir = value;
    else if (key == "--config") config = value;
    else if (key == "--rounds") options.rounds = std::stoi(value);
    else if (key == "--update") options.update = ParseWeightUpdate(value);
    else if (key == "--selection") options.selection = ParseSelection(value);
    else if (key == "--sample_factor") options.sample_factor = std::stod(value);
    else if (key == "--seed") options.seed = std::stoull(value);
    else if (key == "--error_on") options.error_on = ParseErrorMeasure(value);
    else if (key == "--learning_rate") options.learning_rate = std::stod(value);
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  try {
    const auto x = ReadCsv(dir + "/X.csv");
    const auto y = ReadCsv(dir + "/y.csv");
    const auto folds_rows = ReadCsv(dir + "/folds.csv");
    TrainingSet data;
    data.feature_types = {"all"};
    FeatureMatrix m(static_cast<Eigen::Index>(x.size()), static_cast<Eigen::Index>(x.at(0).size()));
    int k = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (std::size_t j = 0; j < x[i].size(); ++j) m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = static_cast<float>(x[i][j]);
      data.labels.push_back(static_cast<int>(y.at(i).at(0)));
      k = std::max(k, data.labels.back() + 1);
    }
    data.features = {m};
    for (int c = 0; c < k; ++c) data.class_names.push_back(std::to_string(c));
    std::vector<int> folds;
    for (const auto& r : folds_rows) folds.push_back(static_cast<int>(r.at(0)));
    if (config == "stumps") {
      BaseSetting stump;
      stump.kind = BaseKind::kDTree;
      stump.tree_max_depth = 1;
      options.base = {stump};
    } else if (config == "full") {
      options.base = DefaultBaseSet();
    } else if (config == "reduced") {
      // The default set less the learners that interpolate their training set (depth-6 trees, 1-NN), which under
      // the whole-set error reach e = 0 and end boosting (the comparison's "full" set before --error_on out_of_bag).
      for (const BaseSetting& s : DefaultBaseSet()) {
        if ((s.kind == BaseKind::kDTree && s.tree_max_depth > 3) || (s.kind == BaseKind::kKnn && s.knn_k < 3)) continue;
        options.base.push_back(s);
      }
    } else {
      std::fprintf(stderr, "config must be stumps, full or reduced\n");
      return 2;
    }
    const auto start = std::chrono::steady_clock::now();
    const CrossValidationReport report = CrossValidate(data, options, folds);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double mean_rounds = 0.0;
    for (int r : report.rounds_per_fold) mean_rounds += static_cast<double>(r) / report.rounds_per_fold.size();
    std::printf("{\"accuracy\": %.4f, \"train_and_test_seconds\": %.3f, \"mean_rounds\": %.1f, \"kinds\": {", 1.0 - report.test_error,
                seconds, mean_rounds);
    for (std::size_t i = 0; i < report.kind_share.size(); ++i) {
      std::printf("%s\"%s\": %.3f", i ? ", " : "", report.kind_share[i].first.c_str(), report.kind_share[i].second);
    }
    std::printf("}}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
