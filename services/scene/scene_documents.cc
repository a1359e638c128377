#include "services/scene/scene_documents_internal.h"
#include "services/scene/scene_stored_documents.h"

#include <cmath>
#include <limits>

namespace anchordb::services::scene_documents {
namespace {

// Non-finite numbers are written as null (nlohmann) and read back as NaN.
double NumberOrNaN(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() || !it->is_number() ? std::numeric_limits<double>::quiet_NaN() : it->get<double>();
}

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

MergedModel MergedModelFromDocument(const Json& j) {
  MergedModel r;
  r.scene_id = j.at("scene").get<std::int64_t>();
  const Json icp = j.value("icp", Json::object());
  r.icp_converged = icp.value("converged", false);
  r.icp_applied = icp.value("applied", false);
  r.fitness_m2 = NumberOrNaN(icp, "fitness_m2");
  r.fitness_before_m2 = NumberOrNaN(icp, "fitness_before_m2");
  const Json correction = icp.value("correction", Json::object());
  // Stored by this code as three numbers (NaN is stored as null); anything else reads as NaN, never as an error.
  const Json t = correction.value("translation_m", Json::array({0.0, 0.0, 0.0}));
  const auto element = [&t](std::size_t k) {
    return t.is_array() && k < t.size() && t[k].is_number() ? t[k].get<double>() : std::nan("");
  };
  r.correction_translation_m = {element(0), element(1), element(2)};
  r.correction_rotation_rad = NumberOrNaN(correction, "rotation_rad");
  r.source_points = icp.value("source_points", std::size_t{0});
  r.target_points = icp.value("target_points", std::size_t{0});
  // Issue 13's fields (absent from older reports: empty, zeros).
  r.icp_verdict = icp.value("verdict", std::string());
  const auto six = [&icp](const char* key, std::array<double, 6>& out) {
    const Json a = icp.value(key, Json::array());
    for (std::size_t k = 0; k < 6; ++k) out[k] = a.is_array() && k < a.size() && a[k].is_number() ? a[k].get<double>() : 0.0;
  };
  six("relative_information", r.relative_information);
  six("remaining_sigma", r.remaining_sigma);
  r.unobservable_directions = icp.value("unobservable_directions", 0);
  r.mahalanobis2 = NumberOrNaN(icp, "mahalanobis2");
  const Json px = j.value("pixels", Json::object());
  r.rasterised = px.value("rasterised", std::size_t{0});
  r.supported = px.value("supported", std::size_t{0});
  r.replaced_farther = px.value("replaced_farther", std::size_t{0});
  r.rear_projected = px.value("rear_projected", std::size_t{0});
  r.filled_unknown = px.value("filled_unknown", std::size_t{0});
  r.rejected_fov = px.value("rejected_fov", std::size_t{0});
  r.rejected_occlusion = px.value("rejected_occlusion", std::size_t{0});
  r.rejected_neighbourhood = px.value("rejected_neighbourhood", std::size_t{0});
  r.rejected_uncertain = px.value("rejected_uncertain", std::size_t{0});
  const Json premises = j.value("premises", Json::object());
  r.tolerance_px = premises.value("tolerance_px", 0.0);
  r.tolerance_m = premises.value("tolerance_m", 0.0);
  r.fallback = premises.value("fallback", std::string());
  return r;
}

// The corrected pose a merge report holds, read back exactly as written (no renormalisation).
Pose3 PoseFromDocument(const Json& j) {
  const Json& p = j.at("position");
  const Json& q = j.at("orientation");
  Pose3 pose;
  pose.position_m = {p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()};
  pose.orientation = Eigen::Quaterniond(q.at(3).get<double>(), q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>());
  return pose;
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

MergeReport MergeReportFromDocument(const Json& j) {
  MergeReport r;
  r.requested = j.value("requested", true);
  r.strategy = ValueOf(kMergeStrategyNames, j.value("strategy", std::string("algorithm2"))).value_or(r.strategy);
  for (const Json& c : j.value("candidates", Json::array())) {
    r.candidates.push_back({c.at("scene").get<std::int64_t>(), NumberOrNaN(c, "overlap")});
  }
  if (j.contains("pending")) r.pending = j["pending"].get<bool>();
  r.performed = j.value("performed", false);
  for (const Json& m : j.value("models_used", Json::array())) r.models_used.push_back(MergedModelFromDocument(m));
  if (j.contains("timing_ms")) {
    const Json& timing = j["timing_ms"];
    r.timing = {NumberOrNaN(timing, "icp"), NumberOrNaN(timing, "rasterise"), NumberOrNaN(timing, "merge")};
  }
  r.superseded = j.value("superseded", std::vector<std::int64_t>{});
  if (j.contains("pose_corrected")) r.X_MapCamera_corrected = PoseFromDocument(j["pose_corrected"]);
  if (j.contains("pose_corrected_by_scene")) r.corrected_by_scene = j["pose_corrected_by_scene"].get<std::int64_t>();
  return r;
}

}  // namespace anchordb::services::scene_documents

namespace anchordb::services::scene_stored {

std::string EncodeMergeReport(const MergeReport& report) { return scene_documents::MergeReportDocument(report).dump(); }

MergeReport DecodeMergeReport(const std::string& stored, std::int64_t scene_id) {
  try {
    return scene_documents::MergeReportFromDocument(json::Json::parse(stored));
  } catch (const json::Json::exception& e) {
    throw Error(ErrorCode::kInternal, "scene " + std::to_string(scene_id) + " has an unreadable merge report: " + e.what());
  }
}

}  // namespace anchordb::services::scene_stored
