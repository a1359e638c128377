// Opening a scene model where earlier ones were taken: candidate selection, the merge of Algorithm 2 on the first
// frame, its report, and supersession (thesis 3.3.2-3.3.4).
#include "services/scene/scene_service.h"
#include "services/scene/scene_service_internal.h"
#include "engine/scene/merge.h"
#include "engine/scene/projection.h"

namespace anchordb::services {

using namespace scene_detail;

Json SceneService::SelectCandidates(const std::string& map, const PinholeIntrinsics& K, const Pose3& pose,
                                    std::int64_t stamp_ns) {
  storage::SceneFilter filter;
  filter.near_m = pose.position_m;
  filter.radius_m = merge_.candidate_radius_m;
  filter.limit = 50;
  const auto records = store_.Read([&](storage::Connection& c) { return storage::ListScenes(c, map, filter); });
  const Eigen::Isometry3d X_MC = engine::ToIsometry(pose);
  Json out = Json::array();
  for (const auto& r : records) {
    if (static_cast<int>(out.size()) >= merge_.max_candidates) break;
    if (r.status == "observing" || r.frames == 0) continue;  // only finished observations with a persisted state
    if (static_cast<double>(stamp_ns - r.started_ns) > merge_.max_age_s * 1e9) continue;
    const auto full = store_.Read([&](storage::Connection& c) { return storage::FindScene(c, map, r.id, true); });
    if (!full || full->background.empty()) continue;
    const PinholeIntrinsics Kj = IntrinsicsFromJson(Json::parse(full->intrinsics_json));
    const auto background = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(Kj.width) * Kj.height);
    std::vector<float> sparse(background.size(), 0.0f);  // every 8th pixel in both directions probes the overlap
    for (int v = 0; v < Kj.height; v += 8) for (int u = 0; u < Kj.width; u += 8) sparse[v * Kj.width + u] = background[v * Kj.width + u];
    const Pose3 pj = json::AsPose3(Json::parse(full->pose_json), "pose");
    const double overlap = engine::FrustumOverlap(engine::BackProject(sparse, Kj, engine::ToIsometry(pj)), K, X_MC,
                                                  merge_.frustum_far_m);
    if (overlap < merge_.min_overlap) continue;
    out.push_back({{"scene", r.id}, {"overlap", overlap}});
  }
  return out;
}

void SceneService::MergeFirstFrame(Model& m, const std::vector<std::uint16_t>& depth, double scale,
                                   const std::vector<std::uint8_t>& dynamic) {
  Json report = Json::parse(m.record.merge_report_json);
  const Pose3 pose = json::AsPose3(Json::parse(m.record.pose_json), "pose");
  const Eigen::Isometry3d X_MC = engine::ToIsometry(pose);
  std::vector<engine::PriorModel> priors;
  std::vector<Pose3> prior_poses;
  for (const Json& c : report["candidates"]) {
    const std::int64_t id = c["scene"].get<std::int64_t>();
    const auto full = store_.Read([&](storage::Connection& conn) { return storage::FindScene(conn, m.record.map_id, id, true); });
    if (!full || full->background.empty()) continue;  // forgotten meanwhile
    engine::PriorModel prior;
    prior.id = id;
    prior.K = IntrinsicsFromJson(Json::parse(full->intrinsics_json));
    prior_poses.push_back(json::AsPose3(Json::parse(full->pose_json), "pose"));
    prior.X_MapCamera = engine::ToIsometry(prior_poses.back());
    prior.background_m = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(prior.K.width) * prior.K.height);
    priors.push_back(std::move(prior));
  }
  engine::MergeParams params;
  params.beta = m.params.beta;
  params.frustum_far_m = merge_.frustum_far_m;
  const std::string strategy = report.value("strategy", "algorithm2");
  params.strategy = strategy == "naive" ? engine::MergeStrategy::kNaive
                    : strategy == "naive_without_icp" ? engine::MergeStrategy::kNaiveWithoutIcp
                                                       : engine::MergeStrategy::kAlgorithm2;
  const engine::MergeResult result = engine::MergeAndApplyFirstFrame(
      m.state, depth, scale, dynamic.empty() ? std::span<const std::uint8_t>() : dynamic, m.params, m.K, X_MC, priors, params);
  Json used = Json::array();
  for (const auto& r : result.models) {
    const Eigen::AngleAxisd aa(r.icp.correction.linear());
    const Eigen::Vector3d t = r.icp.correction.translation();
    used.push_back({{"scene", r.id},
                    {"icp", {{"converged", r.icp.converged}, {"applied", r.icp_applied}, {"fitness_m2", r.icp.fitness_m2}, {"fitness_before_m2", r.icp.fitness_before_m2},
                             {"correction", {{"translation_m", {t.x(), t.y(), t.z()}}, {"rotation_rad", aa.angle()}}},
                             {"source_points", r.icp.source_points}, {"target_points", r.icp.target_points}}},
                    {"pixels", {{"rasterised", r.rasterised_pixels}, {"supported", r.supported},
                                {"replaced_farther", r.replaced_farther}, {"rear_projected", r.rear_projected},
                                {"filled_unknown", r.filled_unknown}, {"rejected_fov", r.rejected_fov},
                                {"rejected_occlusion", r.rejected_occlusion},
                                {"rejected_neighbourhood", r.rejected_neighbourhood}}}});
  }
  // The registration also localises this camera against the earlier models: the best applied ICP correction gives
  // the pose the segments of this model are placed with (X_MC_corrected = X_MC * correction^-1).
  const engine::MergeModelReport* best_icp = nullptr;
  for (const auto& r : result.models) {
    if (r.icp_applied && (!best_icp || r.icp.fitness_m2 < best_icp->icp.fitness_m2)) best_icp = &r;
  }
  if (best_icp) {
    const Eigen::Isometry3d corrected = X_MC * best_icp->icp.correction.inverse();
    const Eigen::Quaterniond q(corrected.linear());
    report["pose_corrected"] = {{"position", {corrected.translation().x(), corrected.translation().y(), corrected.translation().z()}},
                                {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
    report["pose_corrected_by_scene"] = best_icp->id;
  }
  report["performed"] = true;
  report["pending"] = false;
  report["models_used"] = used;
  report["timing_ms"] = {{"icp", result.timing.icp_ms}, {"rasterise", result.timing.rasterise_ms},
                         {"merge", result.timing.merge_ms}};
  // Supersession (3.3.4): earlier models from (nearly) the same viewpoint are now represented by this one.
  Json superseded = Json::array();
  const Eigen::Vector3d view = pose.orientation * Eigen::Vector3d::UnitZ();
  for (std::size_t k = 0; k < priors.size(); ++k) {
    const double distance = (prior_poses[k].position_m - pose.position_m).norm();
    const double angle = std::acos(std::clamp((prior_poses[k].orientation * Eigen::Vector3d::UnitZ()).dot(view), -1.0, 1.0));
    if (distance <= merge_.supersede_distance_m && angle <= merge_.supersede_angle_rad) superseded.push_back(priors[k].id);
  }
  report["superseded"] = superseded;
  m.record.merge_report_json = report.dump();
  const std::int64_t id = m.record.id;
  store_.Write([&](storage::Connection& c) {
    for (const Json& old : superseded) storage::UpdateSceneStatus(c, old.get<std::int64_t>(), "superseded", std::nullopt, id);
  });
  m.last_counts = engine::FrameCounts{};
  for (std::size_t i = 0; i < m.state.movable.size(); ++i) {
    m.last_counts.movable += m.state.movable[i];
    m.last_counts.dynamic += m.state.dynamic[i];
  }
  Persist(m);  // the merge is persisted with the model at once
}

}  // namespace anchordb::services
