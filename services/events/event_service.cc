// Keyframe analysis: segments, change events, instance updates and the lost-key rule (see event_service.h).
#include "services/events/event_service.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>

#include "schema/error.h"
#include "storage/blob_codec.h"
#include "engine/scene/projection.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

using storage::BlobElement;

namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

PinholeIntrinsics IntrinsicsOf(const std::string& intrinsics_json) {
  const Json j = Json::parse(intrinsics_json);
  return {j.at("width").get<int>(), j.at("height").get<int>(), j.at("fx").get<double>(),
          j.at("fy").get<double>(), j.at("cx").get<double>(), j.at("cy").get<double>()};
}

// A stored array as `T`s; `count` > 0 insists on that many (the model's camera).
template <typename T>
std::vector<T> DecodeArray(const std::string& blob, std::size_t count = 0) {
  const auto d = storage::DecodeBlob(blob);
  if (d.bytes.size() % sizeof(T) != 0 || (count && d.bytes.size() != count * sizeof(T))) {
    throw Error(ErrorCode::kInternal, "stored array does not match the camera");
  }
  std::vector<T> out(d.bytes.size() / sizeof(T));
  std::memcpy(out.data(), d.bytes.data(), d.bytes.size());
  return out;
}

std::string EncodePoints(const std::vector<Eigen::Vector3f>& points) {
  std::vector<float> flat;
  flat.reserve(points.size() * 3);
  for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return storage::EncodeBlob(BlobElement::kF32, {static_cast<std::uint32_t>(points.size()), 3}, storage::AsBytes(flat), 1);
}

std::vector<Eigen::Vector3f> DecodePoints(const std::string& blob) {
  std::vector<Eigen::Vector3f> out;
  if (blob.empty()) return out;
  const std::vector<float> flat = DecodeArray<float>(blob);
  for (std::size_t i = 0; i + 2 < flat.size(); i += 3) out.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
  return out;
}

std::string Fixed(double v, int digits = 2) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string Position(const Eigen::Vector3d& p) { return "(" + Fixed(p.x()) + ", " + Fixed(p.y()) + ", " + Fixed(p.z()) + ")"; }

Eigen::Vector3d Vec(const double* v) { return {v[0], v[1], v[2]}; }


std::int64_t StoreSegment(storage::Connection& c, const std::string& map, std::int64_t keyframe, const engine::Segment& s) {
  storage::SegmentRecord r;
  r.map_id = map;
  r.keyframe_id = keyframe;
  for (int k = 0; k < 3; ++k) r.centroid[k] = s.centroid_m[k], r.min[k] = s.min_m[k], r.max[k] = s.max_m[k];
  r.points = s.points;
  r.sample = EncodePoints(s.sample_m);
  return storage::InsertSegment(c, r);
}

Json SegmentJson(const engine::Segment& s) {
  return {{"centroid_m", {s.centroid_m.x(), s.centroid_m.y(), s.centroid_m.z()}},
          {"extent_m", {s.Extent().x(), s.Extent().y(), s.Extent().z()}},
          {"points", s.points}};
}

// Index of the present instance the segment matches best (nearest centroid), or -1.
int BestMatch(const engine::Segment& s, const std::vector<storage::InstanceRecord>& instances,
              const std::vector<bool>& taken, const engine::MatchParams& p) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (taken[i]) continue;
    const Eigen::Vector3d c = Vec(instances[i].position), e = Vec(instances[i].extent);
    if (!engine::Matches(s, c, e, p)) continue;
    const double d = engine::MatchDistance(s, c, e);
    if (d < best_d) best_d = d, best = static_cast<int>(i);
  }
  return best;
}

void Confirm(storage::Connection& c, storage::InstanceRecord& r, const engine::Segment& s, std::int64_t stamp,
             std::int64_t scene) {
  r.last_seen_ns = std::max(r.last_seen_ns, stamp);
  r.last_scene_id = scene;
  r.updated_ns = NowNs();
  r.sample = EncodePoints(s.sample_m);
  storage::UpdateInstance(c, r);
}

std::vector<storage::InstanceRecord> PresentObjects(storage::Connection& c, const std::string& map) {
  storage::InstanceFilter f;
  f.kind = "object";
  f.status = "present";
  f.limit = 100000;
  return storage::ListInstances(c, map, f, true);
}

}  // namespace

EventService::EventService(storage::Store& store, FurnitureService* furniture, EventSettings settings)
    : store_(store), furniture_(furniture), settings_(settings) {}

Json EventService::OnKeyframe(const KeyframeNotice& n) {
  std::lock_guard<std::mutex> lock(analysis_mutex_);
  return store_.Write([&](storage::Connection& c) {
    return n.kind == "begin" ? AnalyseBegin(c, n) : AnalyseLayer(c, n);
  });
}

Json EventService::AddedObject(storage::Connection& c, const std::string& map, const engine::Segment& s,
                               std::int64_t segment_id, const std::string& detection, std::int64_t stamp_ns,
                               std::optional<std::int64_t> scene, std::optional<std::int64_t> layer,
                               std::vector<storage::EvidenceRecord> evidence) {
  const std::int64_t now = NowNs();
  // Lost-key rule (3.3.4): a labelled object removed earlier and not seen since, of similar size.
  storage::InstanceFilter absent;
  absent.kind = "object";
  absent.status = "absent";
  absent.limit = 100000;
  std::optional<storage::InstanceRecord> moved;
  double best_similarity = settings_.move_min_size_similarity;
  std::optional<storage::HistoryRecord> removal;
  // Only an addition seen being made continues a labelled removal: the person observed taking the object is the one
  // observed bringing one (3.5.3); an object that appeared while nobody watched is not taken for it. Size only
  // vetoes clearly different objects (partial views make extents uncertain).
  for (auto& r : detection == "observed" ? storage::ListInstances(c, map, absent, false) : std::vector<storage::InstanceRecord>{}) {
    if (r.status_locked || Json::parse(r.labels_json).empty()) continue;
    const auto history = storage::ListHistory(c, r.id);
    if (history.empty() || history.back().present || history.back().stamp_ns > stamp_ns) continue;
    const double similarity = engine::SizeSimilarity(Vec(r.extent), s.Extent());
    if (similarity >= best_similarity) best_similarity = similarity, moved = r, removal = history.back();
  }
  storage::EventRecord e;
  e.map_id = map;
  e.detection = detection;
  e.stamp_ns = stamp_ns;
  e.scene_id = scene;
  e.action_layer = layer;
  e.segment_id = segment_id;
  e.created_ns = now;
  e.evidence = std::move(evidence);
  Json details = {{"segment", SegmentJson(s)}};
  std::int64_t instance_id = 0;
  if (moved) {
    storage::InstanceRecord r = *moved;
    const Json labels = Json::parse(r.labels_json);
    std::string top;
    double top_w = -1;
    for (auto it = labels.begin(); it != labels.end(); ++it) if (it.value().get<double>() > top_w) top_w = it.value(), top = it.key();
    e.type = "moved";
    e.label = top;
    e.explanation = "inferred move (lost-key rule, thesis 3.3.4): '" + top + "' (instance " + std::to_string(r.id) +
                    ") was removed from " + Position(Vec(removal->position)) +
                    " and has not been seen since; this object was added at " + Position(s.centroid_m) +
                    " by an observed action, without a new label, and is of compatible size (similarity " + Fixed(best_similarity) + ")";
    details["from_m"] = {removal->position[0], removal->position[1], removal->position[2]};
    details["size_similarity"] = best_similarity;
    details["removal_event"] = removal->event_id ? Json(*removal->event_id) : Json(nullptr);
    instance_id = r.id;
    e.instance_id = instance_id;
    e.details_json = details.dump();
    e.id = storage::InsertEvent(c, e);
    r.status = "present";
    for (int k = 0; k < 3; ++k) r.position[k] = s.centroid_m[k], r.extent[k] = s.Extent()[k];
    r.last_seen_ns = stamp_ns;
    if (scene) r.last_scene_id = scene;
    r.sample = EncodePoints(s.sample_m);
    r.updated_ns = now;
    storage::UpdateInstance(c, r);
  } else {
    storage::InstanceRecord r;
    r.map_id = map;
    for (int k = 0; k < 3; ++k) r.position[k] = s.centroid_m[k], r.extent[k] = s.Extent()[k];
    r.last_seen_ns = stamp_ns;
    r.last_scene_id = scene;
    r.sample = EncodePoints(s.sample_m);
    r.created_ns = r.updated_ns = now;
    instance_id = storage::InsertInstance(c, r);
    e.type = "added";
    e.instance_id = instance_id;
    e.explanation = detection == "meanwhile"
                        ? "an object stands in front of the background merged from the earlier visit and matches no "
                          "object known to be there: added while the robot was away"
                        : "an object stands in front of the background at the end of the action layer and did not at its "
                          "start: added while observing";
    e.details_json = details.dump();
    e.id = storage::InsertEvent(c, e);
  }
  storage::HistoryRecord h;
  h.instance_id = instance_id;
  h.stamp_ns = stamp_ns;
  h.present = true;
  for (int k = 0; k < 3; ++k) h.position[k] = s.centroid_m[k];
  h.event_id = e.id;
  storage::AppendHistory(c, h);
  return EventJson(*storage::FindEvent(c, map, e.id));
}

Json EventService::AnalyseBegin(storage::Connection& c, const KeyframeNotice& n) {
  Json events = Json::array();
  engine::ChangeParams p = settings_.change;
  p.beta = n.beta;
  auto present = PresentObjects(c, n.map);
  if (n.merged_scenes.empty() && present.empty()) return {{"events", events}, {"segments", 0}};
  std::vector<storage::EvidenceRecord> before;
  for (std::int64_t scene : n.merged_scenes) {
    if (auto k = storage::LatestKeyframeId(c, scene)) before.push_back({*k, "before"});
  }
  std::vector<bool> taken(present.size(), false);
  int segments = 0;
  if (!n.merged_scenes.empty()) {
    const auto front = engine::InFrontOfBackground(*n.depth_mm, *n.background_mm, p);
    for (const engine::Segment& s : engine::SegmentMask(front, *n.depth_mm, n.K, n.X_MapCamera, p)) {
      ++segments;
      const int match = BestMatch(s, present, taken, settings_.match);
      if (match >= 0) {
        taken[static_cast<std::size_t>(match)] = true;
        Confirm(c, present[static_cast<std::size_t>(match)], s, n.stamp_ns, n.scene_id);
        continue;
      }
      const std::int64_t segment_id = StoreSegment(c, n.map, n.keyframe_id, s);
      auto evidence = before;
      evidence.push_back({n.keyframe_id, "after"});
      events.push_back(AddedObject(c, n.map, s, segment_id, "meanwhile", n.stamp_ns, n.scene_id, 0, evidence));
    }
  }
  // Objects believed present that this view sees through were removed meanwhile.
  for (std::size_t i = 0; i < present.size(); ++i) {
    if (taken[i]) continue;
    storage::InstanceRecord& r = present[i];
    const engine::Visibility v = engine::CheckVisibility(DecodePoints(r.sample), *n.depth_mm, n.K, n.X_MapCamera, p);
    const int judged = v.confirmed + v.seen_through;
    if (judged < settings_.removed_min_visible_points || v.seen_through < settings_.removed_min_seen_through * judged) {
      if (v.confirmed >= settings_.removed_min_visible_points) r.last_seen_ns = n.stamp_ns, storage::UpdateInstance(c, r);
      continue;
    }
    storage::EventRecord e;
    e.map_id = n.map;
    e.type = "removed";
    e.detection = "meanwhile";
    e.stamp_ns = n.stamp_ns;
    e.scene_id = n.scene_id;
    e.action_layer = 0;
    e.instance_id = r.id;
    e.created_ns = NowNs();
    if (r.last_scene_id) {
      if (auto k = storage::LatestKeyframeId(c, *r.last_scene_id)) e.evidence.push_back({*k, "before"});
    }
    e.evidence.push_back({n.keyframe_id, "after"});
    e.explanation = "the view now sees through " + std::to_string(v.seen_through) + " of " + std::to_string(judged) +
                    " measured points of the object last seen at " + Position(Vec(r.position)) +
                    ": removed while the robot was away";
    e.details_json = Json{{"visibility", {{"confirmed", v.confirmed}, {"seen_through", v.seen_through}, {"hidden", v.hidden},
                                          {"unmeasured", v.unmeasured}, {"outside", v.outside}}}}.dump();
    e.id = storage::InsertEvent(c, e);
    r.status = "absent";
    r.updated_ns = e.created_ns;
    r.sample.clear();  // keep the stored sample (COALESCE)
    storage::UpdateInstance(c, r);
    storage::AppendHistory(c, {r.id, 0, n.stamp_ns, false, {r.position[0], r.position[1], r.position[2]}, e.id});
    events.push_back(EventJson(*storage::FindEvent(c, n.map, e.id)));
  }
  return {{"events", events}, {"segments", segments}};
}

Json EventService::AnalyseLayer(storage::Connection& c, const KeyframeNotice& n) {
  Json events = Json::array();
  engine::ChangeParams p = settings_.change;
  p.beta = n.beta;
  // The keyframe that opened this layer: the latest of the scene before this one.
  const auto previous = storage::PreviousKeyframeId(c, n.scene_id, n.keyframe_id);
  if (!previous) return {{"events", events}, {"segments", 0}};
  const auto prev = storage::FindKeyframe(c, n.map, *previous, true);
  const std::size_t count = static_cast<std::size_t>(n.K.width) * n.K.height;
  const std::vector<std::uint16_t> before_mm = DecodeArray<std::uint16_t>(prev->depth, count);
  const engine::ChangeMasks masks = engine::CompareKeyframes(before_mm, *n.depth_mm, *n.background_mm, n.K.width, n.K.height, p);
  engine::ChangeParams no_clean = p;
  no_clean.clean = false;  // CompareKeyframes cleaned already
  auto present = PresentObjects(c, n.map);
  std::vector<bool> taken(present.size(), false);
  const std::int64_t layer = prev->action_layer;
  int segments = 0;
  // Removals first: an object taken and put back elsewhere in one layer is then a removal and an addition.
  for (const engine::Segment& s : engine::SegmentMask(masks.removed, before_mm, n.K, n.X_MapCamera, no_clean)) {
    ++segments;
    const std::int64_t segment_id = StoreSegment(c, n.map, prev->id, s);
    const int match = BestMatch(s, present, taken, settings_.match);
    storage::InstanceRecord r;
    const std::int64_t now = NowNs();
    if (match >= 0) {
      taken[static_cast<std::size_t>(match)] = true;
      r = present[static_cast<std::size_t>(match)];
      if (r.status_locked) continue;
    } else {  // part of the background until now: an instance from here on
      r.map_id = n.map;
      r.status = "absent";
      for (int k = 0; k < 3; ++k) r.position[k] = s.centroid_m[k], r.extent[k] = s.Extent()[k];
      r.last_seen_ns = prev->stamp_ns;
      r.last_scene_id = n.scene_id;
      r.sample = EncodePoints(s.sample_m);
      r.created_ns = r.updated_ns = now;
      r.id = storage::InsertInstance(c, r);
      storage::AppendHistory(c, {r.id, 0, prev->stamp_ns, true, {s.centroid_m.x(), s.centroid_m.y(), s.centroid_m.z()}, std::nullopt});
    }
    storage::EventRecord e;
    e.map_id = n.map;
    e.type = "removed";
    e.detection = "observed";
    e.stamp_ns = n.stamp_ns;
    e.scene_id = n.scene_id;
    e.action_layer = layer;
    e.instance_id = r.id;
    e.segment_id = segment_id;
    e.created_ns = now;
    e.evidence = {{prev->id, "before"}, {n.keyframe_id, "after"}};
    e.explanation = "an object stood in front of the background at the start of the action layer and the sensor sees "
                    "through it at its end: removed while observing";
    e.details_json = Json{{"segment", SegmentJson(s)}}.dump();
    e.id = storage::InsertEvent(c, e);
    r.status = "absent";
    r.updated_ns = now;
    storage::UpdateInstance(c, r);
    storage::AppendHistory(c, {r.id, 0, n.stamp_ns, false, {r.position[0], r.position[1], r.position[2]}, e.id});
    events.push_back(EventJson(*storage::FindEvent(c, n.map, e.id)));
  }
  for (const engine::Segment& s : engine::SegmentMask(masks.added, *n.depth_mm, n.K, n.X_MapCamera, no_clean)) {
    ++segments;
    const int match = BestMatch(s, present, taken, settings_.match);
    if (match >= 0) {  // already known here (e.g. found at the begin keyframe)
      taken[static_cast<std::size_t>(match)] = true;
      Confirm(c, present[static_cast<std::size_t>(match)], s, n.stamp_ns, n.scene_id);
      continue;
    }
    const std::int64_t segment_id = StoreSegment(c, n.map, n.keyframe_id, s);
    events.push_back(AddedObject(c, n.map, s, segment_id, "observed", n.stamp_ns, n.scene_id, layer,
                                 {{prev->id, "before"}, {n.keyframe_id, "after"}}));
  }
  return {{"events", events}, {"segments", segments}, {"action_layer", layer}};
}

Json EventService::Reanalyse(const std::string& map, std::int64_t keyframe_id, const Json& body) {
  json::RejectUnknownKeys(body, {"scene"});
  std::lock_guard<std::mutex> lock(analysis_mutex_);
  return store_.Write([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    const auto kf = storage::FindKeyframe(c, map, keyframe_id, true);
    if (!kf) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(keyframe_id) + " does not exist in map '" + map + "'", "keyframe");
    const auto own = storage::FindScene(c, map, kf->scene_id, false);
    const Pose3 own_pose = json::AsPose3(Json::parse(own->pose_json), "pose");
    // The newer model: the one asked for, else the newest of this place (camera within 0.5 m) with a stored state.
    std::optional<storage::SceneRecord> newer;
    if (body.contains("scene")) {
      const Json& v = body["scene"];
      if (!v.is_number_integer()) throw Error(ErrorCode::kInvalidArgument, "scene must be an integer id", "scene");
      newer = storage::FindScene(c, map, v.get<std::int64_t>(), true);
      if (!newer) throw Error(ErrorCode::kNotFound, "scene " + v.dump() + " does not exist in map '" + map + "'", "scene");
    } else {
      storage::SceneFilter f;
      f.near_m = own_pose.position_m;
      f.radius_m = 0.5;
      f.limit = 20;
      for (const auto& r : storage::ListScenes(c, map, f)) {
        if (r.id <= kf->scene_id || r.frames == 0 || r.forgotten_ns) continue;
        newer = storage::FindScene(c, map, r.id, true);
        break;
      }
      if (!newer) throw Error(ErrorCode::kConflict, "no newer scene model of this place has a background to apply", "scene");
    }
    if (newer->background.empty() || newer->started_ns < kf->stamp_ns) {
      throw Error(ErrorCode::kConflict, "scene " + std::to_string(newer->id) + " is not newer than the keyframe or has no background", "scene");
    }
    const PinholeIntrinsics K_new = IntrinsicsOf(newer->intrinsics_json);
    const std::vector<float> background_m = DecodeArray<float>(newer->background);
    const PinholeIntrinsics K = IntrinsicsOf(own->intrinsics_json);
    const Eigen::Isometry3d X_MC = engine::ToIsometry(own_pose);
    const auto rendered = engine::RenderDepthMm(
        engine::BackProject(background_m, K_new, engine::ToIsometry(json::AsPose3(Json::parse(newer->pose_json), "pose"))), K, X_MC);
    const std::vector<std::uint16_t> depth_mm = DecodeArray<std::uint16_t>(kf->depth);
    engine::ChangeParams p = settings_.change;
    p.beta = Json::parse(own->params_json).value("beta", p.beta);
    const auto front = engine::InFrontOfBackground(depth_mm, rendered, p);
    Json found = Json::array(), events = Json::array();
    storage::InstanceFilter all;
    all.kind = "object";
    all.include_deleted = true;
    all.limit = 100000;
    const auto instances = storage::ListInstances(c, map, all, false);
    const auto newer_keyframe = storage::LatestKeyframeId(c, newer->id);
    const std::int64_t newer_stamp = newer->last_frame_ns.value_or(newer->started_ns);
    for (const engine::Segment& s : engine::SegmentMask(front, depth_mm, K, X_MC, p)) {
      std::optional<std::int64_t> known;
      for (const auto& r : instances) {
        const auto h = storage::HistoryAt(c, r.id, kf->stamp_ns);
        if (h && h->present && engine::Matches(s, Eigen::Vector3d(h->position[0], h->position[1], h->position[2]), Vec(r.extent), settings_.match)) known = r.id;
      }
      Json item = SegmentJson(s);
      item["known_instance"] = known ? Json(*known) : Json(nullptr);
      found.push_back(item);
      if (known) continue;
      // Missed when the keyframe was taken: it stood there then, and the newer background shows the place without it.
      const std::int64_t segment_id = StoreSegment(c, map, kf->id, s);
      const std::int64_t now = NowNs();
      storage::InstanceRecord r;
      r.map_id = map;
      r.status = "absent";
      for (int k = 0; k < 3; ++k) r.position[k] = s.centroid_m[k], r.extent[k] = s.Extent()[k];
      r.last_seen_ns = kf->stamp_ns;
      r.last_scene_id = kf->scene_id;
      r.sample = EncodePoints(s.sample_m);
      r.created_ns = r.updated_ns = now;
      r.id = storage::InsertInstance(c, r);
      storage::EventRecord added;
      added.map_id = map;
      added.type = "added";
      added.detection = "reanalysis";
      added.stamp_ns = kf->stamp_ns;
      added.scene_id = kf->scene_id;
      added.action_layer = kf->action_layer;
      added.instance_id = r.id;
      added.segment_id = segment_id;
      added.created_ns = now;
      added.evidence = {{kf->id, "after"}};
      added.explanation = "keyframe " + std::to_string(kf->id) + " re-analysed with the background of scene " +
                          std::to_string(newer->id) + ": an object stood here then that was part of the background at the time";
      added.details_json = Json{{"segment", SegmentJson(s)}, {"background_scene", newer->id}}.dump();
      added.id = storage::InsertEvent(c, added);
      storage::AppendHistory(c, {r.id, 0, kf->stamp_ns, true, {s.centroid_m.x(), s.centroid_m.y(), s.centroid_m.z()}, added.id});
      storage::EventRecord removed = added;
      removed.type = "removed";
      removed.stamp_ns = std::max(newer_stamp, kf->stamp_ns);
      removed.scene_id = newer->id;
      removed.action_layer = std::nullopt;
      removed.evidence = {{kf->id, "before"}};
      if (newer_keyframe) removed.evidence.push_back({*newer_keyframe, "after"});
      removed.explanation = "the background of scene " + std::to_string(newer->id) + " lies behind where this object stood: "
                            "it is gone";
      removed.id = storage::InsertEvent(c, removed);
      storage::AppendHistory(c, {r.id, 0, removed.stamp_ns, false, {s.centroid_m.x(), s.centroid_m.y(), s.centroid_m.z()}, removed.id});
      events.push_back(EventJson(*storage::FindEvent(c, map, added.id)));
      events.push_back(EventJson(*storage::FindEvent(c, map, removed.id)));
    }
    return Json{{"keyframe", kf->id}, {"background_scene", newer->id}, {"segments", found}, {"events", events}};
  });
}

}  // namespace anchordb::services
