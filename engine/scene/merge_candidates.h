#pragma once
// Which earlier scene models a new one merges (thesis 3.3.3): finished models with a persisted state, not older than
// max_age_s, whose cameras stood within candidate_radius_m and whose static background lies at least min_overlap
// inside the new view frustum; newest first, at most max_candidates. Pure: the backgrounds come from a callback, so
// only the models that pass the cheap checks are loaded, in order.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "engine/scene/merge.h"
#include "engine/scene/projection.h"
#include "schema/types.h"

namespace anchordb::engine {

struct MergeCandidateParams {
  int max_candidates = 5;                 // newest first
  double max_age_s = 30.0 * 24 * 3600;    // older models are not merged
  double candidate_radius_m = 6.0;        // camera positions farther apart are not considered
  double min_overlap = 0.05;              // fraction of the earlier background inside the new view frustum
  double frustum_far_m = 5.0;             // rear boundary of a view frustum (sensor range)
};

// At most this many of the newest models within the radius are examined.
inline constexpr int kMergeCandidatesExamined = 50;

// An earlier model as listed (without its state).
struct EarlierModel {
  std::int64_t id = 0;
  bool observing = false;              // still being observed: not merged
  std::int64_t persisted_frames = 0;   // 0: no state to merge
  std::int64_t started_ns = 0;
  Eigen::Vector3d p_MapCamera_m = Eigen::Vector3d::Zero();
};

// An earlier model's static background and camera.
struct EarlierBackground {
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
  std::vector<float> background_m;  // row-major K.width x K.height, 0 = unknown
};

struct MergeCandidate {
  std::int64_t id = 0;
  double overlap = 0.0;  // fraction of the probed background inside the new view frustum
};

// The cheap checks, before any state is loaded: finished, persisted, young enough (stamp_ns - started_ns <=
// max_age_s), camera within candidate_radius_m of p_MapNew_m.
inline bool MayMerge(const EarlierModel& m, const Eigen::Vector3d& p_MapNew_m, std::int64_t stamp_ns,
                     const MergeCandidateParams& params) {
  if (m.observing || m.persisted_frames == 0) return false;
  if (static_cast<double>(stamp_ns - m.started_ns) > params.max_age_s * 1e9) return false;
  const Eigen::Vector3d d = m.p_MapCamera_m - p_MapNew_m;
  return d.x() * d.x() + d.y() * d.y() + d.z() * d.z() <= params.candidate_radius_m * params.candidate_radius_m;
}

// Fraction of the earlier background, probed at every 8th pixel in both directions, inside the frustum of the new
// camera (K, X_MapCamera, far_m).
inline double ProbeOverlap(const EarlierBackground& earlier, const PinholeIntrinsics& K,
                           const Eigen::Isometry3d& X_MapCamera, double far_m) {
  const PinholeIntrinsics& Kj = earlier.K;
  std::vector<float> sparse(earlier.background_m.size(), 0.0f);
  for (int v = 0; v < Kj.height; v += 8) {
    for (int u = 0; u < Kj.width; u += 8) sparse[v * Kj.width + u] = earlier.background_m[v * Kj.width + u];
  }
  return FrustumOverlap(BackProject(sparse, Kj, earlier.X_MapCamera), K, X_MapCamera, far_m);
}

// Loads an earlier model's background; nullopt when it has none (any more).
using EarlierBackgroundSource = std::function<std::optional<EarlierBackground>(std::int64_t id)>;

// The candidates among `newest_first` (the newest models of the map within the radius) for a new model at
// (K, X_MapCamera) opened at stamp_ns.
inline std::vector<MergeCandidate> SelectMergeCandidates(const std::vector<EarlierModel>& newest_first,
                                                         const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera,
                                                         std::int64_t stamp_ns, const MergeCandidateParams& params,
                                                         const EarlierBackgroundSource& background_of) {
  std::vector<MergeCandidate> out;
  for (const EarlierModel& m : newest_first) {
    if (static_cast<int>(out.size()) >= params.max_candidates) break;
    if (!MayMerge(m, X_MapCamera.translation(), stamp_ns, params)) continue;
    const std::optional<EarlierBackground> earlier = background_of(m.id);
    if (!earlier) continue;
    const double overlap = ProbeOverlap(*earlier, K, X_MapCamera, params.frustum_far_m);
    if (overlap < params.min_overlap) continue;
    out.push_back({m.id, overlap});
  }
  return out;
}

}  // namespace anchordb::engine
