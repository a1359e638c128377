#include "api/scene_documents_json.h"

namespace anchordb::api::scene_documents {

using namespace anchordb::services;

namespace {

Json MergedModelDocument(const MergedModel& r) {
  const Eigen::Vector3d& t = r.correction_translation_m;
  Json out = {{"scene", r.scene_id},
          {"icp", {{"converged", r.icp_converged}, {"applied", r.icp_applied}, {"fitness_m2", r.fitness_m2},
                   {"fitness_before_m2", r.fitness_before_m2},
                   {"correction", {{"translation_m", {t.x(), t.y(), t.z()}}, {"rotation_rad", r.correction_rotation_rad}}},
                   {"source_points", r.source_points}, {"target_points", r.target_points}}},
          {"pixels", {{"rasterised", r.rasterised}, {"supported", r.supported}, {"replaced_farther", r.replaced_farther},
                      {"rear_projected", r.rear_projected}, {"filled_unknown", r.filled_unknown},
                      {"rejected_fov", r.rejected_fov}, {"rejected_occlusion", r.rejected_occlusion},
                      {"rejected_neighbourhood", r.rejected_neighbourhood}}}};
  if (!r.icp_verdict.empty()) {  // issue 13's registration (a report of an older release round-trips unchanged)
    Json& icp = out["icp"];
    icp["verdict"] = r.icp_verdict;
    icp["relative_information"] = r.relative_information;
    icp["unobservable_directions"] = r.unobservable_directions;
    icp["mahalanobis2"] = r.mahalanobis2;
    icp["remaining_sigma"] = r.remaining_sigma;
    out["pixels"]["rejected_uncertain"] = r.rejected_uncertain;
    out["premises"] = {{"tolerance_px", r.tolerance_px}, {"tolerance_m", r.tolerance_m}, {"merged", r.fallback.empty()},
                       {"fallback", r.fallback}};
  }
  return out;
}

}  // namespace

Json CameraDocument(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

Json PoseDocument(const Pose3& pose) { return json::ToJson(pose); }

Json ParamsDocument(const SceneParams& params) {
  return {{"beta", params.model.beta},
          {"dynamic_mode", NameOf(kDynamicModeNames, params.model.dynamic_mode)},
          {"depth_scale", params.depth_scale}};
}

Json MergeReportDocument(const MergeReport& r) {
  Json candidates = Json::array();
  for (const auto& c : r.candidates) candidates.push_back({{"scene", c.id}, {"overlap", c.overlap}});
  Json out = {{"requested", r.requested}, {"strategy", NameOf(kMergeStrategyNames, r.strategy)},
              {"performed", r.performed}, {"candidates", candidates}};
  if (r.pending) out["pending"] = *r.pending;
  if (r.performed) {
    Json used = Json::array();
    for (const auto& m : r.models_used) used.push_back(MergedModelDocument(m));
    out["models_used"] = used;
    out["timing_ms"] = {{"icp", r.timing.icp_ms}, {"rasterise", r.timing.rasterise_ms}, {"merge", r.timing.merge_ms}};
    out["superseded"] = r.superseded;
  }
  if (r.X_MapCamera_corrected) out["pose_corrected"] = PoseDocument(*r.X_MapCamera_corrected);
  if (r.corrected_by_scene) out["pose_corrected_by_scene"] = *r.corrected_by_scene;
  return out;
}

}  // namespace anchordb::api::scene_documents
