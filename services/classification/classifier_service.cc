#include "services/classification/classifier_service.h"

#include <algorithm>
#include <chrono>
#include <set>

#include "engine/classification/cross_validation.h"
#include "schema/error.h"
#include "schema/ids.h"
#include "storage/classifier_documents.h"
#include "storage/feature_repository.h"

namespace anchordb::services {
namespace {

using engine::BaseSetting;

storage::ClassifierBaseSettingRecord SettingRecord(const BaseSetting& s) {
  storage::ClassifierBaseSettingRecord r;
  r.kind = engine::BaseKindName(s.kind);
  r.svm_c = s.svm_c;
  r.svm_gamma = s.svm_gamma;
  r.svm_gamma_per_dim = s.svm_gamma_per_dim;
  r.tree_max_depth = s.tree_max_depth;
  r.tree_min_samples = s.tree_min_samples;
  r.mlp_hidden = s.mlp_hidden;
  r.mlp_iterations = s.mlp_iterations;
  r.knn_k = s.knn_k;
  return r;
}

BaseSetting SettingOf(const storage::ClassifierBaseSettingRecord& r) {
  BaseSetting s;
  s.kind = engine::ParseBaseKind(r.kind);
  s.svm_c = r.svm_c;
  s.svm_gamma = r.svm_gamma;
  s.svm_gamma_per_dim = r.svm_gamma_per_dim;
  s.tree_max_depth = r.tree_max_depth;
  s.tree_min_samples = r.tree_min_samples;
  s.mlp_hidden = r.mlp_hidden;
  s.mlp_iterations = r.mlp_iterations;
  s.knn_k = r.knn_k;
  return s;
}

// The options of a request as stored (and shown with the model), without the samples.
storage::ClassifierOptionsRecord OptionsRecord(const TrainClassifierRequest& r) {
  storage::ClassifierOptionsRecord o;
  o.name = r.name;
  for (const auto& s : r.base) o.base.push_back(SettingRecord(s));
  o.rounds = r.rounds;
  o.selection = engine::SelectionName(r.selection);
  o.sample_factor = r.sample_factor;
  o.folds = r.folds;
  o.seed = r.seed;
  o.update = engine::WeightUpdateName(r.update);
  o.error_on = engine::ErrorMeasureName(r.error_on);
  o.learning_rate = r.learning_rate;
  o.unknown = r.unknown;
  o.unknown_min_share = r.unknown_min_share;
  return o;
}

// The job's request document: the options, the staging number of the samples (kept in memory until the job runs)
// and what the samples are (how many, per class, per feature type the descriptor length) -- not the samples, which
// would fill the jobs table and every job document served.
std::string TrainingJobDocument(const TrainClassifierRequest& r, const engine::TrainingSet& data, std::int64_t staging) {
  storage::ClassifierTrainingRequestRecord d;
  d.options = OptionsRecord(r);
  std::vector<std::int64_t> counts(data.class_names.size(), 0);
  for (int l : data.labels) ++counts[static_cast<std::size_t>(l)];
  for (std::size_t c = 0; c < counts.size(); ++c) d.class_counts.emplace_back(data.class_names[c], counts[c]);
  for (std::size_t t = 0; t < data.feature_types.size(); ++t) d.feature_dims.emplace_back(data.feature_types[t], data.features[t].cols());
  d.sample_count = static_cast<std::int64_t>(data.labels.size());
  d.staging = staging;
  return storage::EncodeClassifierTrainingRequest(d);
}

// The options of a stored document (the samples come from the staging area).
TrainClassifierRequest DecodeOptions(const storage::ClassifierOptionsRecord& o) {
  TrainClassifierRequest r;
  r.name = o.name;
  for (const auto& s : o.base) r.base.push_back(SettingOf(s));
  r.rounds = o.rounds;
  r.selection = engine::ParseSelection(o.selection);
  r.sample_factor = o.sample_factor;
  r.folds = o.folds;
  r.seed = o.seed;
  r.update = engine::ParseWeightUpdate(o.update);
  r.error_on = engine::ParseErrorMeasure(o.error_on);
  r.learning_rate = o.learning_rate;
  r.unknown = o.unknown;
  r.unknown_min_share = o.unknown_min_share;
  return r;
}

// The training set of a request; throws Error naming the field for everything TrainEsamme would refuse and for the
// checks of the request itself.
engine::TrainingSet TrainingSetOf(const TrainClassifierRequest& r) {
  json::CheckId(r.name, "name");
  if (r.samples.empty()) throw Error(ErrorCode::kInvalidArgument, "no samples", "samples");
  engine::TrainingSet data;
  for (const auto& [type, _] : r.samples.front().features) data.feature_types.push_back(type);
  if (data.feature_types.empty()) throw Error(ErrorCode::kInvalidArgument, "samples need at least one feature type", "samples[0].features");
  std::map<std::string, int> class_index;
  std::vector<int> dims(data.feature_types.size(), 0);
  for (std::size_t i = 0; i < r.samples.size(); ++i) {
    const auto& s = r.samples[i];
    const std::string field = "samples[" + std::to_string(i) + "]";
    if (s.label.empty() || s.label.size() > 256) throw Error(ErrorCode::kInvalidArgument, "a label of 1 to 256 characters", field + ".label");
    if (s.features.size() != data.feature_types.size()) {
      throw Error(ErrorCode::kInvalidArgument, "every sample has the same feature types as the first", field + ".features");
    }
    for (std::size_t t = 0; t < data.feature_types.size(); ++t) {
      const auto it = s.features.find(data.feature_types[t]);
      if (it == s.features.end()) {
        throw Error(ErrorCode::kInvalidArgument, "missing feature type '" + data.feature_types[t] + "'", field + ".features");
      }
      if (i == 0) dims[t] = static_cast<int>(it->second.size());
      if (it->second.empty() || static_cast<int>(it->second.size()) != dims[t]) {
        throw Error(ErrorCode::kInvalidArgument, "descriptors of '" + data.feature_types[t] + "' need " + std::to_string(dims[t]) +
                                                     " values (as the first sample)", field + ".features." + data.feature_types[t]);
      }
    }
    if (!class_index.count(s.label)) {
      class_index[s.label] = static_cast<int>(data.class_names.size());
      data.class_names.push_back(s.label);
    }
    data.labels.push_back(class_index[s.label]);
  }
  if (r.unknown && !class_index.count(engine::kUnknownClass)) data.class_names.push_back(engine::kUnknownClass);
  for (std::size_t t = 0; t < data.feature_types.size(); ++t) {
    engine::FeatureMatrix m(static_cast<Eigen::Index>(r.samples.size()), dims[t]);
    for (std::size_t i = 0; i < r.samples.size(); ++i) {
      const auto& v = r.samples[i].features.at(data.feature_types[t]);
      for (int d = 0; d < dims[t]; ++d) m(static_cast<Eigen::Index>(i), d) = v[static_cast<std::size_t>(d)];
    }
    data.features.push_back(std::move(m));
  }
  std::vector<int> counts(data.class_names.size(), 0);
  for (int l : data.labels) ++counts[static_cast<std::size_t>(l)];
  for (std::size_t c = 0; c < counts.size(); ++c) {
    if (counts[c] == 1) {
      throw Error(ErrorCode::kUnprocessable, "class '" + data.class_names[c] + "' has one sample; every class needs two or more",
                  "samples");
    }
  }
  if (r.folds != 0 && (r.folds < 2 || static_cast<std::size_t>(r.folds) > r.samples.size())) {
    throw Error(ErrorCode::kUnprocessable, "folds must be 0 or in [2, number of samples]", "folds");
  }
  return data;
}

engine::EsammeOptions OptionsOf(const TrainClassifierRequest& r) {
  engine::EsammeOptions o;
  o.base = r.base.empty() ? engine::DefaultBaseSet() : r.base;
  o.rounds = r.rounds;
  o.selection = r.selection;
  o.sample_factor = r.sample_factor;
  o.update = r.update;
  o.error_on = r.error_on;
  o.learning_rate = r.learning_rate;
  o.seed = r.seed;
  o.unknown = r.unknown;
  o.unknown_min_share = r.unknown_min_share;
  return o;
}

storage::ClassifierReportRecord ReportRecord(const engine::TrainingSet& data, const engine::EsammeModel& model,
                                             const std::optional<engine::CrossValidationReport>& cv, double train_seconds) {
  storage::ClassifierReportRecord report;
  report.classes = model.class_names;
  report.feature_types = model.feature_types;
  report.samples = static_cast<std::int64_t>(data.labels.size());
  for (const auto& r : model.rounds) {
    report.rounds.push_back({model.settings[static_cast<std::size_t>(r.setting)].Name(),
                             model.feature_types[static_cast<std::size_t>(r.feature_type)], r.error, r.alpha});
  }
  report.train_seconds = train_seconds;
  if (cv) {
    storage::ClassifierCrossValidationRecord c;
    c.folds = cv->folds;
    c.test_error = cv->test_error;
    c.train_error_per_round = cv->train_error_per_round;
    c.test_error_per_round = cv->test_error_per_round;
    c.test_error_worst_fold_per_round = cv->test_error_worst_fold_per_round;
    for (const auto& row : cv->confusion) c.confusion.emplace_back(row.begin(), row.end());
    c.rounds_per_fold.assign(cv->rounds_per_fold.begin(), cv->rounds_per_fold.end());
    c.kind_share = cv->kind_share;
    c.setting_share = cv->setting_share;
    c.feature_share = cv->feature_share;
    report.cross_validation = std::move(c);
  }
  return report;
}

ClassifierView ViewOf(const storage::ClassifierRecord& r) {
  ClassifierView v;
  v.name = r.name;
  v.created_ns = r.created_ns;
  v.options = r.options;
  v.report = r.report;
  if (!r.report.encoded.empty()) {
    try {
      const storage::ClassifierReportRecord report = storage::DecodeClassifierReport(r.report.encoded, "classifier '" + r.name + "''s report");
      v.classes = report.classes;
      v.feature_types = report.feature_types;
      v.rounds = static_cast<int>(report.rounds.size());
    } catch (const Error&) {  // shown as unreadable where the report is written out
    }
  }
  return v;
}

}  // namespace

ClassifierService::ClassifierService(storage::Store& store, JobService& jobs, FeatureService& features, GridService& grid,
                                     const Clock& clock)
    : store_(store), jobs_(jobs), features_(features), grid_(grid), clock_(clock) {
  JobKind kind;
  kind.name = "classifier_train";
  kind.first_stage = "cross-validating";
  kind.check = [](const JobSubmission& s) {  // SubmitTraining validated the samples; the document must decode
    const TrainClassifierRequest r = DecodeOptions(storage::DecodeClassifierTrainingRequest(s.request, "the training request").options);
    json::CheckId(r.name, "name");
  };
  kind.run = [&store = store_, &clock = clock_, staging_area = staging_](JobContext& job) -> std::optional<std::string> {
    const storage::ClassifierTrainingRequestRecord document = storage::DecodeClassifierTrainingRequest(job.request(), "the training request");
    TrainClassifierRequest r = DecodeOptions(document.options);
    {
      std::lock_guard<std::mutex> lock(staging_area->mutex);
      auto it = staging_area->staged.find(document.staging);
      if (it == staging_area->staged.end()) {
        throw Error(ErrorCode::kUnprocessable, "the training samples are gone (server restarted)", "samples");
      }
      r.samples = std::move(it->second.samples);
      staging_area->staged.erase(it);
    }
    const engine::TrainingSet data = TrainingSetOf(r);
    const engine::EsammeOptions options = OptionsOf(r);
    std::optional<engine::CrossValidationReport> cv;
    const auto start = std::chrono::steady_clock::now();
    if (r.folds >= 2) {
      cv = engine::CrossValidate(data, options, engine::StratifiedFolds(data.labels, r.folds, r.seed), [&](int done, int total) {
        job.Progress("cross-validating", 0.8 * done / total);  // throws once cancelled
        return true;
      });
    }
    job.Progress("training", 0.8);
    const engine::EsammeModel model = engine::TrainEsamme(data, options, [&](int done, int total) {
      job.Progress("training", 0.8 + 0.2 * done / total);
      return true;
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    storage::ClassifierRecord stored;
    stored.name = r.name;
    stored.created_ns = clock.NowNs();
    stored.model = engine::EncodeEsamme(model);
    stored.options.encoded = storage::EncodeClassifierOptions(OptionsRecord(r));
    stored.report.encoded = storage::EncodeClassifierReport(ReportRecord(data, model, cv, seconds));
    store.Write([&](storage::Connection& c) { storage::UpsertClassifier(c, stored); });
    storage::ClassifierTrainingResultRecord result{r.name, static_cast<std::int64_t>(model.rounds.size()), seconds, std::nullopt};
    if (cv) result.test_error = cv->test_error;
    return storage::EncodeClassifierTrainingResult(result);
  };
  jobs_.Register(std::move(kind));
}

JobTicket ClassifierService::SubmitTraining(TrainClassifierRequest request) {
  // Everything the job would refuse is refused here, before anything is staged or queued.
  const engine::TrainingSet data = TrainingSetOf(request);
  engine::ValidateTraining(data, OptionsOf(request));
  // Samples of jobs that ended without running (cancelled while queued) are dropped first.
  std::vector<std::pair<std::int64_t, std::int64_t>> waiting;  // staging number, job
  {
    std::lock_guard<std::mutex> lock(staging_->mutex);
    for (const auto& [number, staged] : staging_->staged) {
      if (staged.job != 0) waiting.emplace_back(number, staged.job);
    }
  }
  for (const auto& [number, job] : waiting) {
    bool ended = true;
    try {
      const JobStatus status = jobs_.Get(job).status;
      ended = status == JobStatus::kSucceeded || status == JobStatus::kFailed;
    } catch (const Error&) {
    }
    if (ended) {
      std::lock_guard<std::mutex> lock(staging_->mutex);
      staging_->staged.erase(number);
    }
  }
  std::int64_t staging = 0;
  {
    std::lock_guard<std::mutex> lock(staging_->mutex);
    staging = staging_->next++;
    staging_->staged[staging].samples = std::move(request.samples);
  }
  try {
    JobTicket ticket = jobs_.Submit("classifier_train", std::nullopt, TrainingJobDocument(request, data, staging));
    std::lock_guard<std::mutex> lock(staging_->mutex);
    if (auto it = staging_->staged.find(staging); it != staging_->staged.end()) it->second.job = ticket.job;
    return ticket;
  } catch (...) {
    std::lock_guard<std::mutex> lock(staging_->mutex);
    staging_->staged.erase(staging);
    throw;
  }
}

std::vector<ClassifierView> ClassifierService::List() {
  std::vector<ClassifierView> out;
  for (const auto& r : store_.Read([](storage::Connection& c) { return storage::ListClassifiers(c); })) out.push_back(ViewOf(r));
  return out;
}

ClassifierView ClassifierService::Get(const std::string& name) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::GetClassifier(c, name, false); });
  if (!r) throw Error(ErrorCode::kNotFound, "classifier '" + name.substr(0, 64) + "' does not exist", "name");
  ClassifierView v = ViewOf(*r);
  v.feature_dims = Model(name)->feature_dims;
  return v;
}

std::shared_ptr<const engine::EsammeModel> ClassifierService::Model(const std::string& name) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::GetClassifier(c, name, true); });
  if (!r) throw Error(ErrorCode::kNotFound, "classifier '" + name.substr(0, 64) + "' does not exist", "name");
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = cache_.find(name);
  if (it != cache_.end() && it->second.first == r->created_ns) return it->second.second;
  auto model = std::make_shared<const engine::EsammeModel>(engine::DecodeEsamme(r->model));
  cache_[name] = {r->created_ns, model};
  return model;
}

std::vector<ClassPrediction> ClassifierService::Predict(const std::string& name, const PredictRequest& request) {
  const auto model = Model(name);
  if (request.samples.empty()) throw Error(ErrorCode::kInvalidArgument, "no samples", "samples");
  // A feature type the model was not trained on is a client mistake (a misspelt type would otherwise be ignored).
  for (std::size_t i = 0; i < request.samples.size(); ++i) {
    for (const auto& [type, values] : request.samples[i]) {
      if (std::find(model->feature_types.begin(), model->feature_types.end(), type) == model->feature_types.end()) {
        std::string known;
        for (const auto& t : model->feature_types) known += (known.empty() ? "" : ", ") + t;
        throw Error(ErrorCode::kInvalidArgument, "unknown feature type '" + type.substr(0, 40) + "' (the classifier's types: " +
                                                     known + ")", "samples[" + std::to_string(i) + "].features." + type.substr(0, 40));
      }
    }
  }
  std::vector<engine::FeatureMatrix> features;
  for (std::size_t t = 0; t < model->feature_types.size(); ++t) {
    const std::string& type = model->feature_types[t];
    engine::FeatureMatrix m(static_cast<Eigen::Index>(request.samples.size()), model->feature_dims[t]);
    for (std::size_t i = 0; i < request.samples.size(); ++i) {
      const std::string field = "samples[" + std::to_string(i) + "].features." + type;
      const auto it = request.samples[i].find(type);
      if (it == request.samples[i].end()) throw Error(ErrorCode::kInvalidArgument, "missing feature type '" + type + "'", field);
      if (static_cast<int>(it->second.size()) != model->feature_dims[t]) {
        throw Error(ErrorCode::kInvalidArgument, "needs " + std::to_string(model->feature_dims[t]) + " values", field);
      }
      for (int d = 0; d < model->feature_dims[t]; ++d) m(static_cast<Eigen::Index>(i), d) = it->second[static_cast<std::size_t>(d)];
    }
    features.push_back(std::move(m));
  }
  std::vector<ClassPrediction> out;
  for (const auto& p : engine::PredictEsamme(*model, features, request.rounds)) {
    ClassPrediction c;
    c.label = model->class_names[static_cast<std::size_t>(p.label)];
    for (std::size_t k = 0; k < p.distribution.size(); ++k) c.distribution.emplace_back(model->class_names[k], p.distribution[k]);
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<RoomClassification> ClassifierService::ClassifyRooms(const ClassifyRoomsRequest& request) {
  if (request.regions.empty()) throw Error(ErrorCode::kInvalidArgument, "no regions", "regions");
  const auto model = Model(request.classifier);
  PredictRequest predict;
  std::vector<RoomClassification> out;
  for (std::size_t r = 0; r < request.regions.size(); ++r) {
    RoomClassification room;
    room.id = request.regions[r].id;
    std::map<std::string, std::vector<float>> sample;
    for (std::size_t t = 0; t < model->feature_types.size(); ++t) {
      const std::string& type = model->feature_types[t];
      BowQuery q;
      q.type = type;
      q.polygon_m = request.regions[r].polygon_m;
      BowResult bow;
      try {
        bow = features_.BagOfWords(request.map, q);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::kNotFound || e.field() != "type") throw;
        throw Error(ErrorCode::kUnprocessable, "map '" + request.map + "' has no codebook of '" + type + "'", "classifier");
      }
      if (bow.words != model->feature_dims[t]) {
        throw Error(ErrorCode::kUnprocessable, "the codebook of '" + type + "' has " + std::to_string(bow.words) +
                                                   " words, the classifier expects " + std::to_string(model->feature_dims[t]),
                    "classifier");
      }
      sample[type] = std::vector<float>(bow.histogram.begin(), bow.histogram.end());
      room.features.push_back(bow.features);
    }
    predict.samples.push_back(std::move(sample));
    out.push_back(std::move(room));
  }
  const auto predictions = Predict(request.classifier, predict);
  for (std::size_t r = 0; r < out.size(); ++r) {
    out[r].label = predictions[r].label;
    out[r].distribution = predictions[r].distribution;
    if (!request.into.empty()) {
      PaintLabelRequest paint;
      paint.map = request.map;
      paint.layer = request.into;
      paint.label = out[r].label;
      paint.polygons_map = {request.regions[r].polygon_m};
      grid_.PaintLabel(paint);
    }
  }
  return out;
}

}  // namespace anchordb::services
