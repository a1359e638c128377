#include "api/classifier_json.h"

#include <cmath>

#include "api/classifier_documents_json.h"
#include "api/stored_document_json.h"

namespace anchordb::api {
namespace {

constexpr std::size_t kMaxSamples = 100000;
constexpr std::size_t kMaxValues = 100000;

std::map<std::string, std::vector<float>> AsFeatures(const Json& j, const std::string& field) {
  if (!j.is_object() || j.empty() || j.size() > 32) {
    throw Error(ErrorCode::kInvalidArgument, "features is an object of 1 to 32 feature types", field);
  }
  std::map<std::string, std::vector<float>> out;
  for (const auto& [type, values] : j.items()) {
    const std::string f = field + "." + type;
    if (type.empty() || type.size() > 40) throw Error(ErrorCode::kInvalidArgument, "feature type names have 1 to 40 characters", f);
    if (!values.is_array() || values.empty() || values.size() > kMaxValues) {
      throw Error(ErrorCode::kInvalidArgument, "a descriptor is an array of 1 to 100000 numbers", f);
    }
    std::vector<float>& v = out[type];
    for (const Json& x : values) {
      if (!x.is_number() || !std::isfinite(x.get<double>()) || std::abs(x.get<double>()) > 3e38) {
        throw Error(ErrorCode::kInvalidArgument, "descriptor values must be finite numbers", f);
      }
      v.push_back(static_cast<float>(x.get<double>()));
    }
  }
  return out;
}

std::vector<double> NumberOrList(const Json& j, const std::string& key, double fallback, const std::string& field) {
  if (!j.contains(key)) return {fallback};
  const Json& v = j[key];
  if (v.is_number()) return {json::AsFiniteNumber(v, field + "." + key)};
  if (!v.is_array() || v.empty() || v.size() > 100) throw Error(ErrorCode::kInvalidArgument, key + " is a number or 1-100 numbers", field + "." + key);
  std::vector<double> out;
  for (const Json& x : v) out.push_back(json::AsFiniteNumber(x, field + "." + key));
  return out;
}

int Whole(const Json& j, const std::string& key, int fallback, const std::string& field) {
  const std::int64_t v = json::IntegerOr(j, key, fallback, field);
  if (v < -1000000 || v > 1000000) throw Error(ErrorCode::kInvalidArgument, key + " is out of range", field + "." + key);
  return static_cast<int>(v);
}

void AddBase(const Json& j, const std::string& field, std::vector<engine::BaseSetting>& out) {
  if (!j.is_object()) throw Error(ErrorCode::kInvalidArgument, "a base classifier setting is an object", field);
  json::RejectUnknownKeys(j, {"kind", "C", "gamma", "gamma_per_dim", "max_depth", "min_samples", "hidden", "iterations", "k"},
                          field);
  engine::BaseSetting s;
  s.kind = engine::ParseBaseKind(json::RequireString(j, "kind", 16, field));
  switch (s.kind) {
    case engine::BaseKind::kSvm:
      for (const auto& grid_member : engine::SvmGrid(NumberOrList(j, "C", 1.0, field), NumberOrList(j, "gamma", 0.1, field),
                                                     json::BoolOr(j, "gamma_per_dim", false, field))) {
        out.push_back(grid_member);
      }
      return;
    case engine::BaseKind::kDTree:
      s.tree_max_depth = Whole(j, "max_depth", s.tree_max_depth, field);
      s.tree_min_samples = Whole(j, "min_samples", s.tree_min_samples, field);
      break;
    case engine::BaseKind::kMlp:
      if (j.contains("hidden")) {
        const Json& h = j["hidden"];
        if (!h.is_array() || h.size() > 3) throw Error(ErrorCode::kInvalidArgument, "hidden is 1 to 3 layer sizes", field + ".hidden");
        s.mlp_hidden.clear();
        for (const Json& x : h) {
          if (!x.is_number_integer()) throw Error(ErrorCode::kInvalidArgument, "layer sizes are integers", field + ".hidden");
          s.mlp_hidden.push_back(static_cast<int>(std::clamp<std::int64_t>(x.get<std::int64_t>(), -1, 1000000)));
        }
      }
      s.mlp_iterations = Whole(j, "iterations", s.mlp_iterations, field);
      break;
    case engine::BaseKind::kKnn:
      s.knn_k = Whole(j, "k", s.knn_k, field);
      break;
  }
  out.push_back(s);
}

}  // namespace

services::TrainClassifierRequest ParseTrainClassifierRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"name", "samples", "base", "rounds", "selection", "sample_factor", "folds", "seed", "update",
                                 "error_on", "learning_rate", "unknown", "unknown_min_share"});
  services::TrainClassifierRequest r;
  r.name = json::RequireId(body, "name");
  const Json& samples = json::Require(body, "samples");
  if (!samples.is_array()) throw Error(ErrorCode::kInvalidArgument, "samples is an array", "samples");
  if (samples.size() > kMaxSamples) throw Error(ErrorCode::kPayloadTooLarge, "at most 100000 samples", "samples");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string field = "samples[" + std::to_string(i) + "]";
    const Json& s = samples[i];
    if (!s.is_object()) throw Error(ErrorCode::kInvalidArgument, "a sample is an object", field);
    json::RejectUnknownKeys(s, {"label", "features"}, field);
    r.samples.push_back({json::RequireString(s, "label", 256, field), AsFeatures(json::Require(s, "features", field), field + ".features")});
  }
  if (body.contains("base")) {
    const Json& base = body["base"];
    if (!base.is_array() || base.empty() || base.size() > 1000) {
      throw Error(ErrorCode::kInvalidArgument, "base is an array of 1 to 1000 settings", "base");
    }
    for (std::size_t i = 0; i < base.size(); ++i) AddBase(base[i], "base[" + std::to_string(i) + "]", r.base);
    if (r.base.size() > 1000) throw Error(ErrorCode::kPayloadTooLarge, "at most 1000 base settings (SVM grids included)", "base");
  }
  r.rounds = Whole(body, "rounds", r.rounds, "");
  if (auto sel = json::OptionalString(body, "selection", 16)) r.selection = engine::ParseSelection(*sel);
  r.sample_factor = json::FiniteNumberOr(body, "sample_factor", r.sample_factor);
  r.folds = Whole(body, "folds", r.folds, "");
  const std::int64_t seed = json::IntegerOr(body, "seed", 1);
  if (seed < 0) throw Error(ErrorCode::kInvalidArgument, "seed must not be negative", "seed");
  r.seed = static_cast<std::uint64_t>(seed);
  if (auto update = json::OptionalString(body, "update", 16)) r.update = engine::ParseWeightUpdate(*update);
  if (auto error_on = json::OptionalString(body, "error_on", 16)) r.error_on = engine::ParseErrorMeasure(*error_on);
  r.learning_rate = json::FiniteNumberOr(body, "learning_rate", r.learning_rate);
  r.unknown = json::BoolOr(body, "unknown", false);
  r.unknown_min_share = json::FiniteNumberOr(body, "unknown_min_share", r.unknown_min_share);
  return r;
}

Json ToJson(const services::ClassifierView& v) {
  Json options = StoredDocumentJson(v.options, "classifier '" + v.name + "''s options", [](const std::string& d, const std::string& what) {
    return ToJson(storage::DecodeClassifierOptions(d, what));
  });
  Json report = StoredDocumentJson(v.report, "classifier '" + v.name + "''s report", [](const std::string& d, const std::string& what) {
    return ToJson(storage::DecodeClassifierReport(d, what));
  });
  // A model trained before schema 27: its classes, feature types and rounds as its JSON report has them.
  Json classes = v.classes, feature_types = v.feature_types;
  std::size_t rounds = static_cast<std::size_t>(v.rounds);
  if (v.report.encoded.empty() && report.is_object()) {
    classes = report.value("classes", Json::array());
    feature_types = report.value("feature_types", Json::array());
    rounds = report.value("rounds", Json::array()).size();
  }
  Json j = {{"name", v.name}, {"created", v.created_ns}, {"classes", classes}, {"feature_types", feature_types},
            {"rounds", rounds}};
  if (!v.feature_dims.empty()) j["feature_dims"] = v.feature_dims;
  j["options"] = std::move(options);
  j["report"] = std::move(report);
  return j;
}

services::PredictRequest ParsePredictRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"samples", "rounds"});
  services::PredictRequest r;
  const Json& samples = json::Require(body, "samples");
  if (!samples.is_array()) throw Error(ErrorCode::kInvalidArgument, "samples is an array", "samples");
  if (samples.size() > kMaxSamples) throw Error(ErrorCode::kPayloadTooLarge, "at most 100000 samples", "samples");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string field = "samples[" + std::to_string(i) + "]";
    if (!samples[i].is_object()) throw Error(ErrorCode::kInvalidArgument, "a sample is an object", field);
    json::RejectUnknownKeys(samples[i], {"features", "label"}, field);
    r.samples.push_back(AsFeatures(json::Require(samples[i], "features", field), field + ".features"));
  }
  r.rounds = Whole(body, "rounds", -1, "");
  return r;
}

Json ToJson(const std::vector<services::ClassPrediction>& predictions) {
  Json list = Json::array();
  for (const auto& p : predictions) {
    Json d = Json::object();
    for (const auto& [label, share] : p.distribution) d[label] = share;
    list.push_back({{"label", p.label}, {"distribution", d}});
  }
  return {{"predictions", list}};
}

services::ClassifyRoomsRequest ParseClassifyRoomsRequest(const std::string& map, const Json& body) {
  json::RejectUnknownKeys(body, {"classifier", "regions", "into"});
  services::ClassifyRoomsRequest r;
  r.map = map;
  r.classifier = json::RequireId(body, "classifier");
  if (auto into = json::OptionalString(body, "into", 64)) {
    json::CheckId(*into, "into");
    r.into = *into;
  }
  const Json& regions = json::Require(body, "regions");
  if (!regions.is_array() || regions.empty() || regions.size() > 1000) {
    throw Error(ErrorCode::kInvalidArgument, "regions is an array of 1 to 1000 regions", "regions");
  }
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const std::string field = "regions[" + std::to_string(i) + "]";
    const Json& g = regions[i];
    if (!g.is_object()) throw Error(ErrorCode::kInvalidArgument, "a region is an object", field);
    json::RejectUnknownKeys(g, {"id", "polygon"}, field);
    services::RoomRegion region;
    region.id = json::OptionalString(g, "id", 64, field).value_or(std::to_string(i));
    const Json& polygon = json::Require(g, "polygon", field);
    if (!polygon.is_array() || polygon.size() < 3 || polygon.size() > 10000) {
      throw Error(ErrorCode::kInvalidArgument, "a polygon has 3 to 10000 vertices [x, y]", field + ".polygon");
    }
    for (const Json& v : polygon) region.polygon_m.push_back(json::AsVector2(v, field + ".polygon"));
    r.regions.push_back(std::move(region));
  }
  return r;
}

Json ToJson(const std::vector<services::RoomClassification>& rooms) {
  Json list = Json::array();
  for (const auto& r : rooms) {
    Json d = Json::object();
    for (const auto& [label, share] : r.distribution) d[label] = share;
    list.push_back({{"id", r.id}, {"label", r.label}, {"distribution", d}, {"features", r.features}});
  }
  return {{"regions", list}};
}

}  // namespace anchordb::api
