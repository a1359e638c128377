#pragma once
// Typed request and result of object classification (issue 15 "Object classification"; thesis 4.3): an object
// instance's segment -> its points in the keyframe that saw it -> fpfh / shot / spd features (engine/features) -> one
// bag of words per feature type over the map's codebooks -> the E-SAMME class distribution, stored per instance with
// source "classifier". Dialog and operator labels take precedence (engine/classification/object_labels.h).
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/events/labels.h"

namespace anchordb::services {

struct ClassifyInstanceRequest {
  std::string map;
  std::int64_t instance = 0;
  std::string classifier;
  // Keypoints of the segment lie this far apart [m] (the keyframe default, 0.15 m, gives a small object one or two
  // features); in [0.005, 0.5].
  double keypoint_spacing_m = 0.03;
  // A segment with fewer points is refused (kUnprocessable): too few for descriptors; in [10, 1000000].
  int min_points = 30;
};

struct InstanceClassificationResult {
  std::int64_t instance = 0;
  std::string classifier;
  std::string label;                                         // the most probable class
  std::vector<std::pair<std::string, double>> distribution;  // every class, in the classifier's order
  // True when the classifier's distribution is now the instance's label; false when dialog or an operator named the
  // instance (their label stays; the classification is kept beside it).
  bool applied = false;
  std::string label_source;     // of the instance's labels afterwards: classifier | dialog | operator | none
  engine::LabelWeights labels;  // the instance's label distribution afterwards
  // The "labelled" event (detection "classifier") written when the classification became the instance's label with
  // another most probable class than its previous classification showed; none when a person's label stands, the
  // shown class did not change, or nothing but the rejection class 'unknown' has a share.
  std::optional<std::int64_t> event;
  std::int64_t segment = 0;     // the segment classified
  std::optional<std::int64_t> keyframe;  // whose cloud gave its points (none: the segment's stored sample)
  int points = 0;               // points of the segment classified
  struct PerType {
    std::string type;
    int features = 0;           // extracted from the segment
    std::vector<double> bag;    // the normalised bag of words the classifier saw
  };
  std::vector<PerType> types;   // the classifier's feature types, in its order
};

}  // namespace anchordb::services
