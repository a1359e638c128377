#pragma once
// Typed requests and results of trained classifiers (SPEC §4.6, thesis 4.2): E-SAMME trained as a job with a k-fold
// cross-validation report, stored with the model and reloaded after a restart.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/classification/esamme.h"
#include "storage/classifier_documents.h"
#include "storage/document_codec.h"

namespace anchordb::services {

// One sample: its class and one descriptor per feature type (e.g. a bag of words per type).
struct ClassifierSample {
  std::string label;
  std::map<std::string, std::vector<float>> features;
};

struct TrainClassifierRequest {
  std::string name;  // an id; training again under a name replaces the stored model
  std::vector<ClassifierSample> samples;
  std::vector<engine::BaseSetting> base;  // empty: engine::DefaultBaseSet()
  int rounds = 50;
  engine::Selection selection = engine::Selection::kMaximum;
  double sample_factor = 0.6;
  int folds = 5;  // 0: no cross-validation; else in [2, samples]
  std::uint64_t seed = 1;
  engine::WeightUpdate update = engine::WeightUpdate::kThesis;
  engine::ErrorMeasure error_on = engine::ErrorMeasure::kWhole;
  double learning_rate = 1.0;
  bool unknown = false;
  double unknown_min_share = 0.5;
};

struct ClassifierView {
  std::string name;
  std::int64_t created_ns = 0;
  std::vector<std::string> classes;
  std::vector<std::string> feature_types;
  std::vector<int> feature_dims;
  int rounds = 0;
  // As stored (storage/classifier_documents.h: the training options without the samples, the cross-validation report
  // and the chosen rounds); a model trained before schema 27 has JSON text there (StoredDocument::legacy_json).
  storage::StoredDocument options;
  storage::StoredDocument report;
};

struct PredictRequest {
  std::vector<std::map<std::string, std::vector<float>>> samples;
  int rounds = -1;  // use only the first rounds (< 0: all)
};

struct ClassPrediction {
  std::string label;
  std::vector<std::pair<std::string, double>> distribution;  // every class, in the model's order
};

// Room classification (thesis 4.3): each region's features -> one bag of words per feature type of the classifier
// (the map's codebooks; their word counts must be the classifier's descriptor lengths) -> the class distribution.
struct RoomRegion {
  std::string id;                      // the caller's name for the region (echoed back)
  std::vector<Eigen::Vector2d> polygon_m;  // map frame [m], >= 3 vertices (a vertical prism: every height)
};

struct ClassifyRoomsRequest {
  std::string map;
  std::string classifier;
  std::vector<RoomRegion> regions;
  std::string into;  // a label layer to paint the most probable category into ("": none)
};

struct RoomClassification {
  std::string id;
  std::string label;
  std::vector<std::pair<std::string, double>> distribution;
  std::vector<int> features;  // per feature type of the classifier: how many were inside
};

}  // namespace anchordb::services
