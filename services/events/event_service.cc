// Keyframe analysis and re-analysis: a snapshot read, the computation outside any write transaction (segments,
// visibility, the change decision of engine/events/keyframe_analysis.h), then a short write that re-checks the
// snapshot (see event_service.h).
#include "services/events/event_service.h"

#include "engine/events/rules.h"

#include <algorithm>

#include "engine/events/keyframe_analysis.h"
#include "engine/scene/projection.h"
#include "schema/error.h"
#include "services/common/stored_pose.h"
#include "services/events/event_analysis_internal.h"
#include "services/events/event_records_internal.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

using namespace events_internal;

namespace {

// Optimistic attempts before the analysis is computed inside the write transaction (which cannot be overtaken).
constexpr int kOptimisticAttempts = 3;

// The segments of a keyframe: they depend on its depth (and that of the keyframe that opened its layer) only, so a
// retry reuses them.
struct KeyframeSegments {
  std::optional<std::int64_t> opening_keyframe_id;
  std::int64_t opening_stamp_ns = 0;
  std::int64_t action_layer = 0;
  std::vector<engine::Segment> front, removed, added;
};

// `opening`: the keyframe that opened the layer, with its images (later keyframes only).
KeyframeSegments Segment(const KeyframeNotice& n, const std::optional<storage::KeyframeRecord>& opening,
                         const engine::ChangeParams& p) {
  KeyframeSegments out;
  if (n.kind == "begin") {
    if (n.merged_scenes.empty()) return out;
    const auto front = engine::InFrontOfBackground(n.depth_mm, n.background_mm, p);
    out.front = engine::SegmentMask(front, n.depth_mm, n.K, n.X_MapCamera, p);
    return out;
  }
  if (!opening) return out;
  out.opening_keyframe_id = opening->id;
  out.opening_stamp_ns = opening->stamp_ns;
  out.action_layer = opening->action_layer;
  const std::size_t count = static_cast<std::size_t>(n.K.width) * n.K.height;
  const std::vector<std::uint16_t> before_mm = DecodeDepthMm(opening->depth, count);
  const engine::ChangeMasks masks = engine::CompareKeyframes(before_mm, n.depth_mm, n.background_mm, n.K.width, n.K.height, p);
  engine::ChangeParams no_clean = p;
  no_clean.clean = false;  // CompareKeyframes cleaned already
  out.removed = engine::SegmentMask(masks.removed, before_mm, n.K, n.X_MapCamera, no_clean);
  out.added = engine::SegmentMask(masks.added, n.depth_mm, n.K, n.X_MapCamera, no_clean);
  return out;
}

engine::ChangeSet Decide(const KeyframeNotice& n, const AnalysisInputs& in, const KeyframeSegments& s,
                         const engine::ChangeParams& p, const engine::EventRules& rules) {
  const std::vector<engine::KnownInstance> instances = KnownInstances(in);
  if (n.kind == "begin") {
    engine::BeginKeyframe k;
    k.keyframe_id = n.keyframe_id;
    k.scene_id = n.scene_id;
    k.stamp_ns = n.stamp_ns;
    k.before_keyframes = in.before_keyframes;
    k.front_segments = s.front;
    k.depth_mm = n.depth_mm;
    k.K = n.K;
    k.X_MapCamera = n.X_MapCamera;
    k.change = p;
    return engine::AnalyseBeginKeyframe(k, instances, rules);
  }
  if (!s.opening_keyframe_id) return {};
  engine::LayerKeyframe k;
  k.keyframe_id = n.keyframe_id;
  k.scene_id = n.scene_id;
  k.stamp_ns = n.stamp_ns;
  k.opening_keyframe_id = *s.opening_keyframe_id;
  k.opening_stamp_ns = s.opening_stamp_ns;
  k.action_layer = s.action_layer;
  k.removed_segments = s.removed;
  k.added_segments = s.added;
  return engine::AnalyseLayerKeyframe(k, instances, rules);
}

std::map<std::int64_t, storage::InstanceRecord> ById(const std::vector<storage::InstanceRecord>& records) {
  std::map<std::int64_t, storage::InstanceRecord> out;
  for (const auto& r : records) out.emplace(r.id, r);
  return out;
}

}  // namespace

EventService::EventService(storage::Store& store, FurnitureService* furniture, EventSettings settings, const Clock& clock)
    : store_(store), furniture_(furniture), settings_(settings), clock_(clock),
      where_cache_(static_cast<std::size_t>(std::max(0, settings.where_cache_entries))) {}

std::mutex& EventService::MapMutex(const std::string& map) {
  return map_mutexes_[std::hash<std::string>{}(map) % kMapStripes];
}

engine::EventRules EventService::Rules() const {
  engine::EventRules r;
  r.match = settings_.match;
  r.move_min_size_similarity = settings_.move_min_size_similarity;
  r.removed_min_seen_through = settings_.removed_min_seen_through;
  r.removed_min_visible_points = settings_.removed_min_visible_points;
  return r;
}

std::optional<KeyframeAnalysis> EventService::AnalyseKeyframe(const KeyframeNotice& n, const Claim& claim) {
  std::lock_guard<std::mutex> lock(MapMutex(n.map));
  engine::ChangeParams p = settings_.change;
  p.beta = n.beta;
  const engine::EventRules rules = Rules();
  std::optional<KeyframeSegments> segments;  // kept across attempts
  const auto stale = [&](const AnalysisInputs& in) { return !segments || segments->opening_keyframe_id != in.opening_keyframe_id; };
  struct Snapshot {
    AnalysisInputs in;
    std::optional<storage::KeyframeRecord> opening;  // read when the segments are to be computed
  };
  const auto read = [&](storage::Connection& c) {
    Snapshot s{ReadAnalysisInputs(c, n), std::nullopt};
    if (s.in.opening_keyframe_id && stale(s.in)) {
      s.opening = storage::FindKeyframe(c, n.map, *s.in.opening_keyframe_id, true);
      if (!s.opening) throw Error(ErrorCode::kInternal, "the keyframe that opened the action layer disappeared");
    }
    return s;
  };
  const auto decide = [&](const Snapshot& s) {
    if (stale(s.in)) segments = Segment(n, s.opening, p);
    return Decide(n, s.in, *segments, p, rules);
  };
  const auto summary = [&](std::vector<EventView> events, const engine::ChangeSet& changes) {
    KeyframeAnalysis out{std::move(events), changes.segments_examined, std::nullopt};
    if (segments->opening_keyframe_id) out.action_layer = segments->action_layer;
    return out;
  };
  for (int attempt = 0; attempt < kOptimisticAttempts; ++attempt) {
    const Snapshot s = store_.Read(read);
    const engine::ChangeSet changes = decide(s);
    if (analysis_hook_) analysis_hook_(n.map);
    // nullopt: another writer changed the instances (an empty change set does not depend on them).
    bool claimed = true;
    auto written = store_.Write([&](storage::Connection& c) -> std::optional<std::vector<EventView>> {
      if (!Empty(changes) && !InputsUnchanged(c, n, s.in)) return std::nullopt;
      if (claim && !(claimed = claim(c))) return std::vector<EventView>{};
      return WriteChangeSet(c, n.map, changes, ById(s.in.records), clock_.NowNs());
    });
    if (!claimed) return std::nullopt;
    if (written) return summary(std::move(*written), changes);
  }
  ++analyses_in_write_;
  return store_.Write([&](storage::Connection& c) -> std::optional<KeyframeAnalysis> {
    if (claim && !claim(c)) return std::nullopt;
    const Snapshot s = read(c);
    const engine::ChangeSet changes = decide(s);
    return summary(WriteChangeSet(c, n.map, changes, ById(s.in.records), clock_.NowNs()), changes);
  });
}

ReanalyseResult EventService::Reanalyse(const std::string& map, std::int64_t keyframe_id, const ReanalyseRequest& request) {
  std::lock_guard<std::mutex> lock(MapMutex(map));
  struct Models {
    storage::KeyframeRecord keyframe;
    storage::SceneRecord own, newer;
  };
  const Models m = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    const auto kf = storage::FindKeyframe(c, map, keyframe_id, true);
    if (!kf) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(keyframe_id) + " does not exist in map '" + map + "'", "keyframe");
    const auto own = storage::FindScene(c, map, kf->scene_id, false);
    // The newer model: the one asked for, else the newest of this place (camera within 0.5 m) with a stored state.
    std::optional<storage::SceneRecord> newer;
    if (request.scene_id) {
      newer = storage::FindScene(c, map, *request.scene_id, true);
      if (!newer) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(*request.scene_id) + " does not exist in map '" + map + "'", "scene");
    } else {
      storage::SceneFilter f;
      f.near_m = own->pose.position_m;
      f.radius_m = engine::kReanalysisRadiusM;
      f.limit = engine::kReanalysisCandidates;
      std::vector<engine::ReanalysisCandidate> candidates;
      for (const auto& r : storage::ListScenes(c, map, f)) candidates.push_back({r.id, r.frames, r.forgotten_ns.has_value()});
      if (const auto chosen = engine::ChooseReanalysisModel(kf->scene_id, candidates)) newer = storage::FindScene(c, map, *chosen, true);
      if (!newer) throw Error(ErrorCode::kConflict, "no newer scene model of this place has a background to apply", "scene");
    }
    if (newer->background.empty() || newer->started_ns < kf->stamp_ns) {
      throw Error(ErrorCode::kConflict, "scene " + std::to_string(newer->id) + " is not newer than the keyframe or has no background", "scene");
    }
    return Models{*kf, *own, *newer};
  });
  // The keyframe's raw depth against the newer background rendered into its camera.
  const PinholeIntrinsics& K = m.own.camera;
  const Eigen::Isometry3d X_MC = engine::ToIsometry(StoredPose(m.own));
  const auto rendered = engine::RenderDepthMm(
      engine::BackProject(DecodeF32(m.newer.background), m.newer.camera, engine::ToIsometry(StoredPose(m.newer))), K, X_MC);
  const std::vector<std::uint16_t> depth_mm = DecodeDepthMm(m.keyframe.depth);
  engine::ChangeParams p = settings_.change;
  p.beta = m.own.beta;
  engine::ReanalysedKeyframe k;
  k.keyframe_id = m.keyframe.id;
  k.scene_id = m.keyframe.scene_id;
  k.stamp_ns = m.keyframe.stamp_ns;
  k.action_layer = m.keyframe.action_layer;
  k.background_scene_id = m.newer.id;
  k.background_stamp_ns = m.newer.last_frame_ns.value_or(m.newer.started_ns);
  k.segments = engine::SegmentMask(engine::InFrontOfBackground(depth_mm, rendered, p), depth_mm, K, X_MC, p);
  const auto decide = [&](const ReanalysisInputs& in) {
    if (!in.keyframe_exists) {
      throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(keyframe_id) + " does not exist in map '" + map + "'", "keyframe");
    }
    k.background_keyframe_id = in.background_keyframe_id;
    return engine::ReanalyseKeyframe(k, InstancesAtTime(in), settings_.match);
  };
  const auto result = [&](const engine::Reanalysis& r, std::vector<EventView> events) {
    ReanalyseResult out{m.keyframe.id, m.newer.id, {}, std::move(events)};
    for (std::size_t i = 0; i < k.segments.size(); ++i) out.segments.push_back({engine::Summarise(k.segments[i]), r.known_instance[i]});
    return out;
  };
  const auto read = [&](storage::Connection& c) { return ReadReanalysisInputs(c, map, m.keyframe, m.newer.id); };
  for (int attempt = 0; attempt < kOptimisticAttempts; ++attempt) {
    const ReanalysisInputs in = store_.Read(read);
    const engine::Reanalysis r = decide(in);
    auto written = store_.Write([&](storage::Connection& c) -> std::optional<std::vector<EventView>> {
      if (!SameInputs(read(c), in)) return std::nullopt;
      return WriteChangeSet(c, map, r.changes, {}, clock_.NowNs());
    });
    if (written) return result(r, std::move(*written));
  }
  return store_.Write([&](storage::Connection& c) {
    const engine::Reanalysis r = decide(read(c));
    return result(r, WriteChangeSet(c, map, r.changes, {}, clock_.NowNs()));
  });
}

}  // namespace anchordb::services
