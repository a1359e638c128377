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

SegmentMatchResult MatchSegment(const Footprint& segment, const std::vector<Footprint>& known,
                                const std::vector<bool>& perceived, double match_iou) {
  SegmentMatchResult out;
  bool found = false;
  for (std::size_t i = 0; i < known.size(); ++i) {
    const double iou = FootprintIoU(segment, known[i]);
    if (iou > out.iou) out.iou = iou, out.index = i, found = true;
  }
  if (!found || out.iou < match_iou) return SegmentMatchResult{SegmentMatch::kNewPiece, 0, out.iou};
  const bool is_perceived = out.index < perceived.size() && perceived[out.index];
  out.match = is_perceived ? SegmentMatch::kUpdatePerceivedPiece : SegmentMatch::kKeepOperatorPiece;
  return out;
}

SegmentationParams ParamsForVoxelCentres(SegmentationParams p, double resolution_m) {
  if (!(resolution_m > p.voxel_m)) return p;
  const double area = (p.voxel_m / resolution_m) * (p.voxel_m / resolution_m);
  const auto scaled = [area](std::size_t n, std::size_t least) {
    return std::max<std::size_t>(least, static_cast<std::size_t>(std::lround(static_cast<double>(n) * area)));
  };
  p.min_plane_points = scaled(p.min_plane_points, 3);
  p.min_cluster_points = scaled(p.min_cluster_points, 1);
  p.voxel_m = std::min(1.0, 0.5 * resolution_m);  // half a voxel: each centre in a leaf of its own
  const double link = std::min(0.5, 1.5 * resolution_m);  // across one voxel diagonal in a plane
  p.cluster_tolerance_m = std::max(p.cluster_tolerance_m, link);
  p.core_radius_m = std::max(p.core_radius_m, link);
  p.outlier_radius_m = std::max(p.outlier_radius_m, link);
  p.plane_distance_m = std::max(p.plane_distance_m, std::min(0.5, 0.75 * resolution_m));
  return p;
}

}  // namespace anchordb::engine::segmentation
