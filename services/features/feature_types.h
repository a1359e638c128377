#pragma once
// Typed requests and results of the anchored features capability (SPEC §4.6, thesis 4.3.2). Anchors in the map
// frame [m]; stamps in ns since the Unix epoch.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/features/extraction.h"
#include "engine/features/features.h"
#include "storage/feature_documents.h"
#include "storage/feature_repository.h"

namespace anchordb::services {

struct FeatureSettings {
  // De-duplication thresholds per type (anchor distance [m], descriptor distance); client types use `other`.
  engine::DedupThreshold fpfh{0.02, 5.0};
  engine::DedupThreshold shot{0.02, 0.1};
  engine::DedupThreshold spd{0.10, 0.05};
  engine::DedupThreshold other{0.02, 0.0};
  int max_batch = 10000;      // features in one client batch
  int max_codebook_words = 4096;
  engine::ExtractionParams extraction;
  bool extract_every_keyframe = false;  // extract fpfh, shot and spd from every new keyframe (after its write)
};

// Server-side extraction from one keyframe's cloud (types a subset of fpfh, shot, spd).
struct ExtractRequest {
  std::vector<std::string> types{"fpfh", "shot", "spd"};
};

struct ExtractResult {
  std::int64_t keyframe = 0;
  int points = 0;  // of the keyframe's cloud
  struct PerType {
    std::string type;
    int extracted = 0;
    int inserted = 0;
    int duplicates = 0;
  };
  std::vector<PerType> types;
  double extract_seconds = 0.0;  // PCL time, outside the write lock
};

struct FeatureItem {
  std::vector<float> descriptor;
  Eigen::Vector3d anchor_m = Eigen::Vector3d::Zero();
  std::optional<std::int64_t> keyframe;  // must be a keyframe of the map
};

// A client batch of one type. The stamp of each feature: `stamp_ns`, else its keyframe's, else now.
struct FeatureBatch {
  std::string type;
  std::optional<std::int64_t> stamp_ns;
  std::vector<FeatureItem> features;
};

struct FeatureBatchResult {
  int inserted = 0;
  int duplicates = 0;
  // Per item, in order: the new feature's id, or the id of the stored feature it duplicates.
  std::vector<std::int64_t> ids;
  std::vector<bool> duplicate;
};

using Feature = storage::FeatureRecord;
using FeatureQuery = storage::FeatureFilter;  // limit in [1, 10000]

struct FeaturePage {
  std::vector<Feature> features;
  std::optional<std::int64_t> next_after;  // set when the page is full
};

struct CodebookRequest {
  std::string type;
  int words = 64;
  std::uint64_t seed = 1;
};

using CodebookView = storage::CodebookRecord;

// The features of one type inside a sphere, a box or a vertical prism over a polygon (map frame); exactly one.
struct BowQuery {
  std::string type;
  std::optional<Eigen::Vector3d> near_m;
  double radius_m = 0.0;
  std::optional<Eigen::Vector3d> box_min_m, box_max_m;
  std::vector<Eigen::Vector2d> polygon_m;  // >= 3 vertices (x, y)
  std::optional<std::int64_t> since_ns, until_ns;
};

struct BowResult {
  std::string type;
  int words = 0;
  int features = 0;               // features inside
  std::vector<double> histogram;  // normalised (sums to 1; all 0 when no feature is inside)
};

}  // namespace anchordb::services
