#include "engine/segmentation/segment_decisions.h"

#include <algorithm>
#include <cmath>

namespace anchordb::engine::segmentation {

std::vector<std::int64_t> SegmentEvidence(const std::vector<Eigen::Vector3f>& points_m, const std::vector<KeyframeView>& keyframes,
                                          double max_range_m, const EvidenceRule& rule) {
  std::vector<std::int64_t> out;
  const std::size_t step = std::max<std::size_t>(1, points_m.size() / std::max<std::size_t>(1, rule.samples));
  for (const KeyframeView& view : keyframes) {
    const Eigen::Isometry3d X_CameraMap = view.X_MapCamera.inverse();
    int seen = 0, tried = 0;
    for (std::size_t i = 0; i < points_m.size(); i += step) {
      ++tried;
      const Eigen::Vector3d p_C = X_CameraMap * points_m[i].cast<double>();
      if (p_C.z() <= rule.min_depth_m || p_C.z() > max_range_m) continue;
      const double u = view.K.fx * p_C.x() / p_C.z() + view.K.cx, v = view.K.fy * p_C.y() / p_C.z() + view.K.cy;
      if (u < 0 || v < 0 || u >= view.K.width || v >= view.K.height) continue;
      const std::size_t pixel = static_cast<std::size_t>(v) * static_cast<std::size_t>(view.K.width) + static_cast<std::size_t>(u);
      if (pixel >= view.depth_mm.size()) continue;  // an image smaller than its camera says: nothing measured there
      const std::uint16_t d = view.depth_mm[pixel];
      if (d > 0 && std::abs(d / 1000.0 - p_C.z()) < rule.depth_tolerance_m) ++seen;
    }
    if (tried > 0 && seen * rule.seen_share_denominator >= tried) out.push_back(view.keyframe);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<double> PriorTimesVerification(std::vector<double> prior, const std::vector<std::string>& category_ids,
                                           const std::vector<std::pair<std::string, double>>& scores, double unknown_floor) {
  double total = 0.0;
  for (const auto& score : scores) total += score.second;
  if (!(total > 0.0)) return prior;  // no ray voted: the prior alone
  double sum = 0.0;
  for (std::size_t i = 0; i < category_ids.size() && i < prior.size(); ++i) {
    double q = unknown_floor;
    for (const auto& score : scores) {
      if (score.first == category_ids[i]) q = unknown_floor + score.second;
    }
    sum += prior[i] *= q;
  }
  if (sum > 0.0) {
    for (double& x : prior) x /= sum;
  }
  return prior;
}

std::map<std::string, double> AverageCategoryShares(const std::map<std::string, double>& old_shares, double observations,
                                                    const std::vector<std::string>& category_ids, const std::vector<double>& p) {
  std::map<std::string, double> out;
  for (std::size_t i = 0; i < category_ids.size() && i < p.size(); ++i) {
    const auto it = old_shares.find(category_ids[i]);
    out[category_ids[i]] = ((it == old_shares.end() ? 0.0 : it->second) * observations + p[i]) / (observations + 1.0);
  }
  return out;
}

}  // namespace anchordb::engine::segmentation
