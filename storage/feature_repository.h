#pragma once
// Rows of anchored features, codebooks and trained classifiers (migrations/0012_features.sql). Anchors are in the map
// frame [m]; spatial queries go through the feature_anchors R*Tree.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "storage/connection.h"
#include "storage/document_codec.h"

namespace anchordb::storage {

struct FeatureRecord {
  std::int64_t id = 0;                     // assigned on insert
  std::string map;
  std::string type;
  std::vector<float> descriptor;
  Eigen::Vector3d anchor_m = Eigen::Vector3d::Zero();  // in the map frame
  std::optional<std::int64_t> keyframe;
  std::int64_t stamp_ns = 0;
  std::optional<int> codeword;
};

// A listing: every given filter must hold. The box and the sphere are in the map frame [m].
struct FeatureFilter {
  std::string type;  // "" = every type
  std::optional<Eigen::Vector3d> box_min_m, box_max_m;
  std::optional<Eigen::Vector3d> near_m;
  double radius_m = 0.0;  // with near_m
  std::optional<std::int64_t> since_ns, until_ns;  // stamp in [since, until)
  std::optional<std::int64_t> keyframe;
  std::int64_t after_id = 0;
  int limit = 1000;
  bool descriptors = true;  // false: descriptor left empty (cheaper)
};

// Inserts `f` (id ignored) and returns its id. Descriptor stored as a float32 blob.
std::int64_t InsertFeature(Connection& c, const FeatureRecord& f);
std::vector<FeatureRecord> ListFeatures(Connection& c, const std::string& map, const FeatureFilter& filter);
// The descriptor length of the features of `type` in `map` already stored, or nullopt when there are none.
std::optional<int> StoredFeatureDims(Connection& c, const std::string& map, const std::string& type);
// Features of `type` within `radius_m` of `anchor_m` (R*Tree box, then exact distance).
std::vector<FeatureRecord> FeaturesNear(Connection& c, const std::string& map, const std::string& type,
                                        const Eigen::Vector3d& anchor_m, double radius_m);
void SetCodeword(Connection& c, std::int64_t feature_id, int codeword);
std::int64_t CountFeatures(Connection& c, const std::string& map, const std::string& type);
// Deletes one feature (its anchor row goes with it).
void DeleteFeature(Connection& c, std::int64_t feature_id);

struct CodebookRecord {
  std::string map;
  std::string type;
  int words = 0;
  int dims = 0;
  std::uint64_t seed = 0;
  std::vector<float> centres;  // words x dims, row-major
  std::int64_t features = 0;
  std::int64_t created_ns = 0;
};
void UpsertCodebook(Connection& c, const CodebookRecord& book);
std::optional<CodebookRecord> GetCodebook(Connection& c, const std::string& map, const std::string& type);

struct ClassifierRecord {
  std::string name;
  std::int64_t created_ns = 0;
  std::string model;  // engine/classification EncodeEsamme blob
  // Encoded (storage/classifier_documents.h: ClassifierOptionsRecord / ClassifierReportRecord); a row written before migration 0027
  // holds the JSON text an earlier version wrote instead (legacy_json), for the HTTP edge to show as it was.
  StoredDocument options;
  StoredDocument report;
};
void UpsertClassifier(Connection& c, const ClassifierRecord& r);
std::optional<ClassifierRecord> GetClassifier(Connection& c, const std::string& name, bool with_model);
std::vector<ClassifierRecord> ListClassifiers(Connection& c);  // without models, by name

}  // namespace anchordb::storage
