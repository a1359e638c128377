#include "api/classifier_documents_json.h"

#include "api/job_json.h"

namespace anchordb::api {
namespace {

using json::Json;

// A base setting with the parameters of its kind only.
Json SettingJson(const storage::ClassifierBaseSettingRecord& s) {
  Json j = {{"kind", s.kind}};
  if (s.kind == "svm") {
    j["C"] = s.svm_c;
    j["gamma"] = s.svm_gamma;
    if (s.svm_gamma_per_dim) j["gamma_per_dim"] = true;
  } else if (s.kind == "dtree") {
    j["max_depth"] = s.tree_max_depth;
    j["min_samples"] = s.tree_min_samples;
  } else if (s.kind == "mlp") {
    j["hidden"] = s.mlp_hidden;
    j["iterations"] = s.mlp_iterations;
  } else if (s.kind == "knn") {
    j["k"] = s.knn_k;
  }
  return j;
}

template <typename T>
Json Named(const std::vector<std::pair<std::string, T>>& items) {
  Json j = Json::object();
  for (const auto& [name, value] : items) j[name] = value;
  return j;
}

}  // namespace

Json ToJson(const storage::ClassifierOptionsRecord& o) {
  Json base = Json::array();
  for (const auto& s : o.base) base.push_back(SettingJson(s));
  return {{"name", o.name}, {"base", base}, {"rounds", o.rounds}, {"selection", o.selection},
          {"sample_factor", o.sample_factor}, {"folds", o.folds}, {"seed", o.seed}, {"update", o.update},
          {"error_on", o.error_on}, {"learning_rate", o.learning_rate}, {"unknown", o.unknown},
          {"unknown_min_share", o.unknown_min_share}};
}

Json ToJson(const storage::ClassifierReportRecord& r) {
  Json rounds = Json::array();
  for (const auto& round : r.rounds) {
    rounds.push_back({{"setting", round.setting}, {"feature_type", round.feature_type}, {"error", round.error},
                      {"alpha", round.alpha}});
  }
  Json j = {{"classes", r.classes}, {"feature_types", r.feature_types}, {"samples", r.samples}, {"rounds", rounds},
            {"train_seconds", r.train_seconds}};
  if (const auto& cv = r.cross_validation) {
    j["cross_validation"] = {{"folds", cv->folds}, {"test_error", cv->test_error},
                             {"train_error_per_round", cv->train_error_per_round},
                             {"test_error_per_round", cv->test_error_per_round},
                             {"test_error_worst_fold_per_round", cv->test_error_worst_fold_per_round},
                             {"confusion", cv->confusion}, {"rounds_per_fold", cv->rounds_per_fold},
                             {"kind_share", Named(cv->kind_share)}, {"setting_share", Named(cv->setting_share)},
                             {"feature_share", Named(cv->feature_share)}};
  }
  return j;
}

Json ToJson(const storage::ClassifierTrainingRequestRecord& r) {
  Json j = ToJson(r.options);
  j["sample_count"] = r.sample_count;
  j["class_counts"] = Named(r.class_counts);
  j["feature_dims"] = Named(r.feature_dims);
  j["staging"] = r.staging;
  return j;
}

Json ToJson(const storage::ClassifierTrainingResultRecord& r) {
  Json j = {{"name", r.name}, {"rounds", r.rounds}, {"train_seconds", r.train_seconds}};
  if (r.test_error) j["test_error"] = *r.test_error;
  return j;
}

void RegisterClassifierJobDocumentWriters() {
  RegisterJobDocumentWriters(
      "classifier_train",
      {[](const std::string& d, const std::string& what) { return ToJson(storage::DecodeClassifierTrainingRequest(d, what)); },
       [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeClassifierTrainingResult(d, what)); }});
}

}  // namespace anchordb::api
