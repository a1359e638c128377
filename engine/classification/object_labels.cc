#include "engine/classification/object_labels.h"

#include "engine/classification/esamme.h"

namespace anchordb::engine {

const char* LabelSourceName(LabelSource source) {
  switch (source) {
    case LabelSource::kNone: return "none";
    case LabelSource::kDialog: return "dialog";
    case LabelSource::kOperator: return "operator";
    case LabelSource::kClassifier: return "classifier";
  }
  return "none";
}

std::optional<std::string> ShownClassifierClass(const EffectiveLabels& labels) {
  if (labels.source != LabelSource::kClassifier || labels.distribution.empty()) return std::nullopt;
  return TopLabel(labels.distribution);
}

bool ClassifierLabelApplies(const LabelWeights& named, bool label_locked) {
  if (label_locked) return false;
  for (const auto& [label, weight] : named) {
    if (weight > 0.0) return false;
  }
  return true;
}

EffectiveLabels EffectiveObjectLabels(const LabelWeights& named, bool label_locked,
                                      const std::optional<LabelWeights>& classified) {
  EffectiveLabels out;
  if (!ClassifierLabelApplies(named, label_locked)) {
    out.distribution = LabelDistribution(named);
    out.source = label_locked ? LabelSource::kOperator : LabelSource::kDialog;
    return out;
  }
  if (!classified) return out;
  LabelWeights kept;
  for (const auto& [label, share] : *classified) {
    if (share > 0.0 && label != kUnknownClass) kept[label] = share;
  }
  if (kept.empty()) return out;
  out.distribution = LabelDistribution(kept);
  out.source = LabelSource::kClassifier;
  return out;
}

std::vector<Eigen::Vector3f> PointsInBox(const std::vector<Eigen::Vector3f>& cloud_m, const Eigen::Vector3d& min_m,
                                         const Eigen::Vector3d& max_m, double margin_m) {
  std::vector<Eigen::Vector3f> out;
  if (!(margin_m >= 0.0) || (min_m.array() > max_m.array()).any()) return out;
  const Eigen::Vector3f lo = (min_m.array() - margin_m).cast<float>().matrix();
  const Eigen::Vector3f hi = (max_m.array() + margin_m).cast<float>().matrix();
  for (const Eigen::Vector3f& p : cloud_m) {
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) out.push_back(p);
  }
  return out;
}

}  // namespace anchordb::engine
