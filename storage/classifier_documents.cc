#include "storage/classifier_documents.h"

#include <type_traits>

#include "storage/document_codec.h"

namespace anchordb::storage {
namespace {
constexpr std::uint16_t kClassifierDocumentVersion = 1;

void PutBaseSetting(DocumentWriter& w, const ClassifierBaseSettingRecord& s) {
  w.Text(s.kind).Real(s.svm_c).Real(s.svm_gamma).Bool(s.svm_gamma_per_dim).Int(s.tree_max_depth).Int(s.tree_min_samples)
      .Count(s.mlp_hidden.size());
  for (const int neurons : s.mlp_hidden) w.Int(neurons);
  w.Int(s.mlp_iterations).Int(s.knn_k);
}

ClassifierBaseSettingRecord TakeBaseSetting(DocumentReader& d) {
  ClassifierBaseSettingRecord s;
  s.kind = d.Text();
  s.svm_c = d.Real();
  s.svm_gamma = d.Real();
  s.svm_gamma_per_dim = d.Bool();
  s.tree_max_depth = d.SmallInt();
  s.tree_min_samples = d.SmallInt();
  for (std::size_t n = d.Count(); n > 0; --n) s.mlp_hidden.push_back(d.SmallInt());
  s.mlp_iterations = d.SmallInt();
  s.knn_k = d.SmallInt();
  return s;
}

void PutClassifierOptions(DocumentWriter& w, const ClassifierOptionsRecord& o) {
  w.Text(o.name).Count(o.base.size());
  for (const auto& s : o.base) PutBaseSetting(w, s);
  w.Int(o.rounds).Text(o.selection).Real(o.sample_factor).Int(o.folds).Int(static_cast<std::int64_t>(o.seed))
      .Text(o.update).Text(o.error_on).Real(o.learning_rate).Bool(o.unknown).Real(o.unknown_min_share);
}

ClassifierOptionsRecord TakeClassifierOptions(DocumentReader& d) {
  ClassifierOptionsRecord o;
  o.name = d.Text();
  for (std::size_t n = d.Count(); n > 0; --n) o.base.push_back(TakeBaseSetting(d));
  o.rounds = d.SmallInt();
  o.selection = d.Text();
  o.sample_factor = d.Real();
  o.folds = d.SmallInt();
  o.seed = static_cast<std::uint64_t>(d.Int());
  o.update = d.Text();
  o.error_on = d.Text();
  o.learning_rate = d.Real();
  o.unknown = d.Bool();
  o.unknown_min_share = d.Real();
  return o;
}

template <typename T>
void PutNamed(DocumentWriter& w, const std::vector<std::pair<std::string, T>>& items) {
  w.Count(items.size());
  for (const auto& [name, value] : items) {
    w.Text(name);
    if constexpr (std::is_same_v<T, double>) w.Real(value); else w.Int(value);
  }
}

template <typename T>
std::vector<std::pair<std::string, T>> TakeNamed(DocumentReader& d) {
  std::vector<std::pair<std::string, T>> out;
  for (std::size_t n = d.Count(); n > 0; --n) {
    std::string name = d.Text();
    if constexpr (std::is_same_v<T, double>) out.emplace_back(std::move(name), d.Real());
    else out.emplace_back(std::move(name), d.Int());
  }
  return out;
}

void PutCrossValidation(DocumentWriter& w, const ClassifierCrossValidationRecord& cv) {
  w.Int(cv.folds).Real(cv.test_error).Reals(cv.train_error_per_round).Reals(cv.test_error_per_round)
      .Reals(cv.test_error_worst_fold_per_round).Count(cv.confusion.size());
  for (const auto& row : cv.confusion) w.Ints(row);
  w.Ints(cv.rounds_per_fold);
  PutNamed(w, cv.kind_share);
  PutNamed(w, cv.setting_share);
  PutNamed(w, cv.feature_share);
}

ClassifierCrossValidationRecord TakeCrossValidation(DocumentReader& d) {
  ClassifierCrossValidationRecord cv;
  cv.folds = d.Int();
  cv.test_error = d.Real();
  cv.train_error_per_round = d.Reals();
  cv.test_error_per_round = d.Reals();
  cv.test_error_worst_fold_per_round = d.Reals();
  for (std::size_t n = d.Count(); n > 0; --n) cv.confusion.push_back(d.Ints());
  cv.rounds_per_fold = d.Ints();
  cv.kind_share = TakeNamed<double>(d);
  cv.setting_share = TakeNamed<double>(d);
  cv.feature_share = TakeNamed<double>(d);
  return cv;
}

}  // namespace

std::string EncodeClassifierOptions(const ClassifierOptionsRecord& options) {
  DocumentWriter w(DocumentKind::kClassifierOptions, kClassifierDocumentVersion);
  PutClassifierOptions(w, options);
  return w.Finish();
}

ClassifierOptionsRecord DecodeClassifierOptions(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kClassifierOptions, kClassifierDocumentVersion, what);
  ClassifierOptionsRecord o = TakeClassifierOptions(d);
  d.End();
  return o;
}

std::string EncodeClassifierReport(const ClassifierReportRecord& r) {
  DocumentWriter w(DocumentKind::kClassifierReport, kClassifierDocumentVersion);
  w.Texts(r.classes).Texts(r.feature_types).Int(r.samples).Count(r.rounds.size());
  for (const auto& round : r.rounds) w.Text(round.setting).Text(round.feature_type).Real(round.error).Real(round.alpha);
  w.Real(r.train_seconds).Bool(r.cross_validation.has_value());
  if (r.cross_validation) PutCrossValidation(w, *r.cross_validation);
  return w.Finish();
}

ClassifierReportRecord DecodeClassifierReport(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kClassifierReport, kClassifierDocumentVersion, what);
  ClassifierReportRecord r;
  r.classes = d.Texts();
  r.feature_types = d.Texts();
  r.samples = d.Int();
  for (std::size_t n = d.Count(); n > 0; --n) {
    ClassifierRoundRecord round;
    round.setting = d.Text();
    round.feature_type = d.Text();
    round.error = d.Real();
    round.alpha = d.Real();
    r.rounds.push_back(std::move(round));
  }
  r.train_seconds = d.Real();
  if (d.Bool()) r.cross_validation = TakeCrossValidation(d);
  d.End();
  return r;
}

std::string EncodeClassifierTrainingRequest(const ClassifierTrainingRequestRecord& r) {
  DocumentWriter w(DocumentKind::kClassifierTrainingRequest, kClassifierDocumentVersion);
  PutClassifierOptions(w, r.options);
  w.Int(r.sample_count);
  PutNamed(w, r.class_counts);
  PutNamed(w, r.feature_dims);
  w.Int(r.staging);
  return w.Finish();
}

ClassifierTrainingRequestRecord DecodeClassifierTrainingRequest(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kClassifierTrainingRequest, kClassifierDocumentVersion, what);
  ClassifierTrainingRequestRecord r;
  r.options = TakeClassifierOptions(d);
  r.sample_count = d.Int();
  r.class_counts = TakeNamed<std::int64_t>(d);
  r.feature_dims = TakeNamed<std::int64_t>(d);
  r.staging = d.Int();
  d.End();
  return r;
}

std::string EncodeClassifierTrainingResult(const ClassifierTrainingResultRecord& r) {
  return DocumentWriter(DocumentKind::kClassifierTrainingResult, kClassifierDocumentVersion)
      .Text(r.name)
      .Int(r.rounds)
      .Real(r.train_seconds)
      .Optional(r.test_error)
      .Finish();
}

ClassifierTrainingResultRecord DecodeClassifierTrainingResult(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kClassifierTrainingResult, kClassifierDocumentVersion, what);
  ClassifierTrainingResultRecord r;
  r.name = d.Text();
  r.rounds = d.Int();
  r.train_seconds = d.Real();
  r.test_error = d.OptionalReal();
  d.End();
  return r;
}

}  // namespace anchordb::storage
