// Opening a scene model where earlier ones were taken: candidate selection, the merge of Algorithm 2 on the first
// frame, its report, and supersession (thesis 3.3.2-3.3.4). The rules are in engine/scene (merge_candidates.h,
// merge.h, supersession.h); here the earlier models are read in one snapshot, merged outside any write, and the
// result is committed by a short write that first checks that the earlier models are still as read.
#include "engine/scene/merge.h"
#include "engine/scene/projection.h"
#include "services/common/stored_pose.h"
#include "services/scene/scene_pose_covariance.h"
#include "services/scene/scene_service.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

namespace scene_detail {

// What the merge depends on of an earlier model's row (nullopt: gone). In scene_detail rather than file-local: it is a
// member type of SceneService::PriorSnapshot.
struct ModelStamp {
  bool exists = false;
  std::string status;
  std::optional<std::int64_t> superseded_by;
  std::int64_t state_version = 0;
  std::int64_t frames = 0;
  std::optional<std::int64_t> forgotten_ns;
  bool operator==(const ModelStamp&) const = default;
};

ModelStamp StampOf(const std::optional<storage::SceneRecord>& r) {
  if (!r) return {};
  return {true, r->status, r->superseded_by, r->state_version, r->frames, r->forgotten_ns};
}

}  // namespace scene_detail

namespace {

MergedModel ReportOf(const engine::MergeModelReport& r) {
  MergedModel m;
  m.scene_id = r.id;
  m.icp_converged = r.icp.converged;
  m.icp_applied = r.icp_applied;
  m.fitness_m2 = r.icp.fitness_m2;
  m.fitness_before_m2 = r.icp.fitness_before_m2;
  m.correction_translation_m = r.icp.correction.translation();
  m.correction_rotation_rad = Eigen::AngleAxisd(r.icp.correction.linear()).angle();
  m.source_points = r.icp.source_points;
  m.target_points = r.icp.target_points;
  m.icp_verdict = r.icp.verdict;
  m.relative_information = r.icp.relative_information;
  m.unobservable_directions = r.icp.unobservable_directions;
  m.mahalanobis2 = r.icp.mahalanobis2;
  for (int k = 0; k < 6; ++k) m.remaining_sigma[k] = std::sqrt(std::max(0.0, r.icp.covariance(k, k)));
  m.rasterised = r.rasterised_pixels;
  m.supported = r.supported;
  m.replaced_farther = r.replaced_farther;
  m.rear_projected = r.rear_projected;
  m.filled_unknown = r.filled_unknown;
  m.rejected_fov = r.rejected_fov;
  m.rejected_occlusion = r.rejected_occlusion;
  m.rejected_neighbourhood = r.rejected_neighbourhood;
  m.rejected_uncertain = r.rejected_uncertain;
  m.tolerance_px = r.tolerance_px;
  m.tolerance_m = r.tolerance_m;
  m.fallback = r.fallback;
  return m;
}

}  // namespace

struct SceneService::PriorSnapshot {
  std::vector<engine::PriorModel> priors;
  std::vector<Pose3> poses;                             // of the priors
  std::vector<std::pair<std::int64_t, ModelStamp>> stamps;  // of every candidate, as read
};

std::vector<engine::MergeCandidate> SceneService::SelectCandidates(const std::string& map, const OpenSceneRequest& request,
                                                                   std::int64_t stamp_ns) {
  storage::SceneFilter filter;
  filter.near_m = request.X_MapCamera.position_m;
  filter.radius_m = merge_.candidate_radius_m;
  filter.limit = engine::kMergeCandidatesExamined;
  std::vector<engine::EarlierModel> earlier;
  for (const auto& r : store_.Read([&](storage::Connection& c) { return storage::ListScenes(c, map, filter); })) {
    earlier.push_back({r.id, r.status == "observing", r.frames, r.started_ns, r.pose.position_m});
  }
  const auto background_of = [&](std::int64_t id) -> std::optional<engine::EarlierBackground> {
    const auto full = store_.Read([&](storage::Connection& c) { return storage::FindScene(c, map, id, true); });
    if (!full || full->background.empty()) return std::nullopt;
    engine::EarlierBackground e;
    e.K = full->camera;
    e.X_MapCamera = engine::ToIsometry(StoredPose(*full));
    e.background_m = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(e.K.width) * e.K.height);
    return e;
  };
  return engine::SelectMergeCandidates(earlier, request.camera, engine::ToIsometry(request.X_MapCamera), stamp_ns, merge_,
                                       background_of);
}

SceneService::PriorSnapshot SceneService::ReadPriors(const Model& m) {
  return store_.Read([&](storage::Connection& c) {
    PriorSnapshot s;
    for (const engine::MergeCandidate& candidate : m.merge.candidates) {
      const auto full = storage::FindScene(c, m.record.map_id, candidate.id, true);
      s.stamps.emplace_back(candidate.id, StampOf(full));
      if (!full || full->background.empty()) continue;  // forgotten meanwhile
      engine::PriorModel prior;
      prior.id = candidate.id;
      prior.K = full->camera;
      s.poses.push_back(StoredPose(*full));
      prior.X_MapCamera = engine::ToIsometry(s.poses.back());
      prior.pose_covariance_map = scene_pose::StoredOrDefault(full->pose_covariance, merge_);
      prior.background_m = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(prior.K.width) * prior.K.height);
      s.priors.push_back(std::move(prior));
    }
    return s;
  });
}

FrameResult SceneService::AddMergingFrame(Model& m, const std::vector<std::uint16_t>& depth, double scale,
                                          const std::vector<std::uint8_t>& dynamic, std::int64_t stamp_ns,
                                          const std::optional<storage::JournalFrame>& journal) {
  const Pose3 pose = StoredPose(m.record);
  const Eigen::Isometry3d X_MC = engine::ToIsometry(pose);
  engine::MergeParams params;
  params.beta = m.params.model.beta;
  params.frustum_far_m = merge_.frustum_far_m;
  params.strategy = m.merge.strategy;
  params.current_pose_covariance_map = scene_pose::StoredOrDefault(m.record.pose_covariance, merge_);
  // Read, merge without holding the write lock, then commit if the earlier models are still as read; the merge is
  // redone once from a fresh read if they changed meanwhile. The merged state is checkpointed with the frame (its
  // journal row, its begin keyframe) in one transaction, so a replay never merges again.
  for (int attempt = 0; attempt < 2; ++attempt) {
    const PriorSnapshot snapshot = ReadPriors(m);
    engine::SceneModelState state = m.state;  // fresh: the merge builds the first state
    const engine::MergeResult result = engine::MergeAndApplyFirstFrame(
        state, depth, scale, dynamic.empty() ? std::span<const std::uint8_t>() : dynamic, m.params.model, m.K, X_MC,
        snapshot.priors, params);
    MergeReport report = m.merge;
    for (const auto& r : result.models) report.models_used.push_back(ReportOf(r));
    if (const auto corrected = engine::CorrectedCameraPose(result, X_MC)) {
      Pose3 p;
      p.position_m = corrected->X_MapCamera_corrected.translation();
      p.orientation = Eigen::Quaterniond(corrected->X_MapCamera_corrected.linear());
      report.X_MapCamera_corrected = p;
      report.corrected_by_scene = corrected->model_id;
    }
    report.performed = true;
    report.pending = false;
    report.timing = result.timing;
    // Supersession (3.3.4): earlier models from (nearly) the same viewpoint are now represented by this one.
    for (std::size_t k = 0; k < snapshot.priors.size(); ++k) {
      if (engine::Supersedes(pose, snapshot.poses[k], merge_)) report.superseded.push_back(snapshot.priors[k].id);
    }
    storage::SceneRecord merged = m.record;
    merged.merge_report = scene_stored::EncodeMergeReport(report);
    engine::FrameCounts counts;  // the merged model's labels
    for (std::size_t i = 0; i < state.movable.size(); ++i) {
      counts.movable += state.movable[i];
      counts.dynamic += state.dynamic[i];
    }
    FrameStep step = Step(m, state, counts, depth, scale, stamp_ns, journal, &merged);
    const bool committed = WriteFrame(m, step, [&](storage::Connection& c) {
      for (const auto& [id, stamp] : snapshot.stamps) {
        if (!(StampOf(storage::FindScene(c, m.record.map_id, id, false)) == stamp)) return false;
      }
      for (std::int64_t old : report.superseded) storage::UpdateSceneStatus(c, old, "superseded", std::nullopt, m.record.id);
      return true;
    });
    if (!committed) continue;
    m.state = std::move(state);
    m.SetMergeReport(std::move(report));
    return FrameCommitted(m, step);
  }
  throw Error(ErrorCode::kConflict, "the earlier scene models merged into scene " + std::to_string(m.record.id) +
                                        " changed during the merge twice; send the frame again", "scene");
}

}  // namespace anchordb::services
