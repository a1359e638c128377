// A scene model's merge report between the service's MergeReport and the store's typed record (see
// scene_stored_documents.h).
#include "schema/error.h"
#include "services/scene/scene_stored_documents.h"

namespace anchordb::services::scene_stored {

namespace {

std::array<double, 3> Stored(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

storage::MergedModelRecord StoredModel(const MergedModel& m) {
  storage::MergedModelRecord r;
  r.scene_id = m.scene_id;
  r.icp_converged = m.icp_converged;
  r.icp_applied = m.icp_applied;
  r.fitness_m2 = m.fitness_m2;
  r.fitness_before_m2 = m.fitness_before_m2;
  r.correction_translation_m = Stored(m.correction_translation_m);
  r.correction_rotation_rad = m.correction_rotation_rad;
  r.source_points = static_cast<std::int64_t>(m.source_points);
  r.target_points = static_cast<std::int64_t>(m.target_points);
  r.icp_verdict = m.icp_verdict;
  r.relative_information = m.relative_information;
  r.unobservable_directions = m.unobservable_directions;
  r.mahalanobis2 = m.mahalanobis2;
  r.remaining_sigma = m.remaining_sigma;
  r.rasterised_px = static_cast<std::int64_t>(m.rasterised);
  r.supported_px = static_cast<std::int64_t>(m.supported);
  r.replaced_farther_px = static_cast<std::int64_t>(m.replaced_farther);
  r.rear_projected_px = static_cast<std::int64_t>(m.rear_projected);
  r.filled_unknown_px = static_cast<std::int64_t>(m.filled_unknown);
  r.rejected_fov_px = static_cast<std::int64_t>(m.rejected_fov);
  r.rejected_occlusion_px = static_cast<std::int64_t>(m.rejected_occlusion);
  r.rejected_neighbourhood_px = static_cast<std::int64_t>(m.rejected_neighbourhood);
  r.rejected_uncertain_px = static_cast<std::int64_t>(m.rejected_uncertain);
  r.tolerance_px = m.tolerance_px;
  r.tolerance_m = m.tolerance_m;
  r.fallback = m.fallback;
  return r;
}

// A count the database holds below zero is no count this release wrote.
std::size_t Count(std::int64_t n, std::int64_t scene_id) {
  if (n < 0) throw Error(ErrorCode::kInternal, "scene " + std::to_string(scene_id) + " has a negative count in its merge report");
  return static_cast<std::size_t>(n);
}

MergedModel ModelOf(const storage::MergedModelRecord& r, std::int64_t scene_id) {
  MergedModel m;
  m.scene_id = r.scene_id;
  m.icp_converged = r.icp_converged;
  m.icp_applied = r.icp_applied;
  m.fitness_m2 = r.fitness_m2;
  m.fitness_before_m2 = r.fitness_before_m2;
  m.correction_translation_m = {r.correction_translation_m[0], r.correction_translation_m[1], r.correction_translation_m[2]};
  m.correction_rotation_rad = r.correction_rotation_rad;
  m.source_points = Count(r.source_points, scene_id);
  m.target_points = Count(r.target_points, scene_id);
  m.icp_verdict = r.icp_verdict;
  m.relative_information = r.relative_information;
  m.unobservable_directions = static_cast<int>(r.unobservable_directions);
  m.mahalanobis2 = r.mahalanobis2;
  m.remaining_sigma = r.remaining_sigma;
  m.rasterised = Count(r.rasterised_px, scene_id);
  m.supported = Count(r.supported_px, scene_id);
  m.replaced_farther = Count(r.replaced_farther_px, scene_id);
  m.rear_projected = Count(r.rear_projected_px, scene_id);
  m.filled_unknown = Count(r.filled_unknown_px, scene_id);
  m.rejected_fov = Count(r.rejected_fov_px, scene_id);
  m.rejected_occlusion = Count(r.rejected_occlusion_px, scene_id);
  m.rejected_neighbourhood = Count(r.rejected_neighbourhood_px, scene_id);
  m.rejected_uncertain = Count(r.rejected_uncertain_px, scene_id);
  m.tolerance_px = r.tolerance_px;
  m.tolerance_m = r.tolerance_m;
  m.fallback = r.fallback;
  return m;
}

}  // namespace

storage::MergeReportRecord EncodeMergeReport(const MergeReport& report) {
  storage::MergeReportRecord r;
  r.requested = report.requested;
  r.strategy = NameOf(kMergeStrategyNames, report.strategy);
  for (const auto& c : report.candidates) r.candidates.push_back({c.id, c.overlap});
  r.pending = report.pending;
  r.performed = report.performed;
  for (const auto& m : report.models_used) r.models_used.push_back(StoredModel(m));
  r.icp_ms = report.timing.icp_ms;
  r.rasterise_ms = report.timing.rasterise_ms;
  r.merge_ms = report.timing.merge_ms;
  r.superseded = report.superseded;
  if (report.X_MapCamera_corrected) {
    const Pose3& p = *report.X_MapCamera_corrected;
    const Eigen::Quaterniond& q = p.orientation;
    r.pose_corrected = std::array<double, 7>{p.position_m.x(), p.position_m.y(), p.position_m.z(), q.x(), q.y(), q.z(), q.w()};
  }
  r.corrected_by_scene = report.corrected_by_scene;
  return r;
}

MergeReport DecodeMergeReport(const storage::MergeReportRecord& r, std::int64_t scene_id) {
  MergeReport report;
  report.requested = r.requested;
  const auto strategy = ValueOf(kMergeStrategyNames, r.strategy);
  if (!strategy) {
    throw Error(ErrorCode::kInternal, "scene " + std::to_string(scene_id) + " has an unknown merge strategy '" + r.strategy + "'");
  }
  report.strategy = *strategy;
  for (const auto& c : r.candidates) report.candidates.push_back({c.scene_id, c.overlap});
  report.pending = r.pending;
  report.performed = r.performed;
  for (const auto& m : r.models_used) report.models_used.push_back(ModelOf(m, scene_id));
  report.timing = {r.icp_ms, r.rasterise_ms, r.merge_ms};
  report.superseded = r.superseded;
  if (r.pose_corrected) {
    const auto& p = *r.pose_corrected;
    Pose3 pose;
    pose.position_m = {p[0], p[1], p[2]};
    pose.orientation = Eigen::Quaterniond(p[6], p[3], p[4], p[5]);  // read back exactly as written
    report.X_MapCamera_corrected = pose;
  }
  report.corrected_by_scene = r.corrected_by_scene;
  return report;
}

}  // namespace anchordb::services::scene_stored
