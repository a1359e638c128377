#pragma once
// Object classification (thesis 4.3, issue 15 "Object classification"): which points of a keyframe belong to an
// instance's segment, and which label distribution of an instance counts. A person's word always wins: a label from
// dialog or an operator is the instance's distribution; a classifier's distribution stands only for an instance
// nobody has named, and is replaced by any later dialog or operator label (it never adds to or overrides theirs).
// Points in the map frame [m].
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/events/labels.h"

namespace anchordb::engine {

// Where an instance's label distribution comes from.
enum class LabelSource { kNone, kDialog, kOperator, kClassifier };
// "none" | "dialog" | "operator" | "classifier".
const char* LabelSourceName(LabelSource source);

struct EffectiveLabels {
  LabelWeights distribution;  // normalised (sums to 1), or empty for kNone
  LabelSource source = LabelSource::kNone;
};

// The distribution that counts for an instance: `named` (the weights from dialog, or an operator's label when
// `label_locked`) when it has any label; else `classified` (a classifier's class distribution; classes of share 0
// and the rejection class "unknown" left out); else none.
EffectiveLabels EffectiveObjectLabels(const LabelWeights& named, bool label_locked,
                                      const std::optional<LabelWeights>& classified);

// Whether a classification of the instance would be its label (false when dialog or an operator named it).
bool ClassifierLabelApplies(const LabelWeights& named, bool label_locked);

// The class an instance shows when its labels are a classifier's (their most probable class, TopLabel); nullopt for
// a person's label or none. A classification whose shown class changes is a 'labelled' event.
std::optional<std::string> ShownClassifierClass(const EffectiveLabels& labels);

// The points of `cloud_m` inside the axis-aligned box [min_m - margin_m, max_m + margin_m] (a segment's bounds).
// A negative margin or an inverted box gives none.
std::vector<Eigen::Vector3f> PointsInBox(const std::vector<Eigen::Vector3f>& cloud_m, const Eigen::Vector3d& min_m,
                                         const Eigen::Vector3d& max_m, double margin_m);

}  // namespace anchordb::engine
