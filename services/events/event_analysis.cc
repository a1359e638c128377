// Reading, re-checking and writing what a keyframe analysis computes (see event_analysis_internal.h).
#include "services/events/event_analysis_internal.h"

#include <algorithm>
#include <iterator>
#include <map>

#include "schema/error.h"
#include "services/events/event_records_internal.h"
#include "storage/scene_repository.h"

namespace anchordb::services::events_internal {
namespace {

std::vector<storage::InstanceRecord> Objects(storage::Connection& c, const std::string& map, const char* status,
                                             bool with_sample, bool include_deleted = false) {
  storage::InstanceFilter f;
  f.kind = "object";
  if (status) f.status = status;
  f.include_deleted = include_deleted;
  f.limit = 100000;
  return storage::ListInstances(c, map, f, with_sample);
}

template <typename T>
bool SameList(const std::vector<std::optional<T>>& a, const std::vector<std::optional<T>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].has_value() != b[i].has_value() || (a[i] && !SameRecord(*a[i], *b[i]))) return false;
  }
  return true;
}

bool SameRecords(const std::vector<storage::InstanceRecord>& a, const std::vector<storage::InstanceRecord>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) if (!SameRecord(a[i], b[i])) return false;
  return true;
}

std::optional<engine::HistoryPoint> PointOf(const std::optional<storage::HistoryRecord>& h) {
  if (!h) return std::nullopt;
  engine::HistoryPoint p{h->stamp_ns, h->present, Vec(h->position), std::nullopt};
  if (h->event_id) p.event = engine::Ref::Existing(*h->event_id);
  return p;
}

// The id of a reference, once the change set's new rows have ids.
std::int64_t Resolve(const engine::Ref& r, const std::vector<std::int64_t>& new_ids) {
  return r.is_new() ? new_ids.at(static_cast<std::size_t>(r.new_index)) : r.id;
}

storage::EventRecord EventRecordOf(const std::string& map, const engine::NewEvent& e, std::int64_t now_ns,
                                   const std::vector<std::int64_t>& segment_ids, const std::vector<std::int64_t>& instance_ids,
                                   const std::vector<std::int64_t>& event_ids) {
  storage::EventRecord r;
  r.map_id = map;
  r.type = engine::EventTypeName(e.type);
  r.detection = engine::DetectionName(e.detection);
  r.stamp_ns = e.stamp_ns;
  r.scene_id = e.scene_id;
  r.action_layer = e.action_layer;
  r.instance_id = Resolve(e.instance, instance_ids);
  if (e.segment) r.segment_id = segment_ids.at(static_cast<std::size_t>(*e.segment));
  r.label = e.label;
  r.explanation = e.explanation;
  r.created_ns = now_ns;
  for (const auto& k : e.evidence) r.evidence.push_back({k.keyframe_id, k.role});
  EventDetails d;
  d.segment = e.segment_summary;
  d.visibility = e.visibility;
  d.background_scene = e.background_scene;
  if (e.move) {
    d.move = MoveEvidence{e.move->from_m, e.move->size_similarity, std::nullopt};
    if (e.move->removal_event) d.move->removal_event = Resolve(*e.move->removal_event, event_ids);
  }
  r.details = StoredEventDetails(d);
  return r;
}

}  // namespace

AnalysisInputs ReadAnalysisInputs(storage::Connection& c, const KeyframeNotice& n) {
  AnalysisInputs in;
  in.instance_version = storage::InstanceVersion(c, n.map);  // the same snapshot as the rows below
  const bool begin = n.kind == "begin";
  if (begin) {
    for (std::int64_t scene : n.merged_scenes) {
      if (auto k = storage::LatestKeyframeId(c, scene)) in.before_keyframes.push_back(*k);
    }
  } else {
    in.opening_keyframe_id = storage::PreviousKeyframeId(c, n.scene_id, n.keyframe_id);
  }
  std::vector<storage::InstanceRecord> present = Objects(c, n.map, "present", true), absent = Objects(c, n.map, "absent", false);
  in.records.reserve(present.size() + absent.size());
  std::merge(std::make_move_iterator(present.begin()), std::make_move_iterator(present.end()),
             std::make_move_iterator(absent.begin()), std::make_move_iterator(absent.end()), std::back_inserter(in.records),
             [](const storage::InstanceRecord& a, const storage::InstanceRecord& b) { return a.id < b.id; });
  for (const storage::InstanceRecord& r : in.records) {
    std::optional<storage::HistoryRecord> last;
    if (r.status == "absent" && !r.status_locked && !r.labels.empty()) {
      const auto history = storage::ListHistory(c, r.id);
      if (!history.empty()) last = history.back();
    }
    in.last_history.push_back(last);
    std::optional<std::int64_t> keyframe;
    if (begin && r.status == "present" && r.last_scene_id) keyframe = storage::LatestKeyframeId(c, *r.last_scene_id);
    in.last_keyframe.push_back(keyframe);
  }
  return in;
}

bool InputsUnchanged(storage::Connection& c, const KeyframeNotice& n, const AnalysisInputs& in) {
  if (storage::InstanceVersion(c, n.map) != in.instance_version) return false;
  if (n.kind != "begin") return storage::PreviousKeyframeId(c, n.scene_id, n.keyframe_id) == in.opening_keyframe_id;
  std::vector<std::int64_t> before;
  for (std::int64_t scene : n.merged_scenes) {
    if (auto k = storage::LatestKeyframeId(c, scene)) before.push_back(*k);
  }
  if (before != in.before_keyframes) return false;
  // The latest keyframe of each present object's last scene, once per scene.
  std::map<std::int64_t, std::optional<std::int64_t>> latest;
  for (std::size_t i = 0; i < in.records.size(); ++i) {
    const storage::InstanceRecord& r = in.records[i];
    if (r.status != "present" || !r.last_scene_id) continue;
    auto [at, added] = latest.try_emplace(*r.last_scene_id);
    if (added) at->second = storage::LatestKeyframeId(c, *r.last_scene_id);
    if (at->second != in.last_keyframe[i]) return false;
  }
  return true;
}

std::vector<engine::KnownInstance> KnownInstances(const AnalysisInputs& in) {
  std::vector<engine::KnownInstance> out;
  for (std::size_t i = 0; i < in.records.size(); ++i) {
    const storage::InstanceRecord& r = in.records[i];
    engine::KnownInstance k;
    k.id = r.id;
    k.present = r.status == "present";
    k.status_locked = r.status_locked;
    k.labels = r.labels;
    k.position_m = Vec(r.position);
    k.extent_m = Vec(r.extent);
    k.sample_m = DecodePoints(r.sample);
    k.last_seen_ns = r.last_seen_ns;
    k.last_keyframe_id = in.last_keyframe[i];
    k.last_history = PointOf(in.last_history[i]);
    out.push_back(std::move(k));
  }
  return out;
}

ReanalysisInputs ReadReanalysisInputs(storage::Connection& c, const std::string& map, const storage::KeyframeRecord& keyframe,
                                      std::int64_t background_scene_id) {
  ReanalysisInputs in;
  in.keyframe_exists = storage::FindKeyframe(c, map, keyframe.id, false).has_value();
  in.records = Objects(c, map, nullptr, false, true);
  for (const auto& r : in.records) in.at_keyframe.push_back(storage::HistoryAt(c, r.id, keyframe.stamp_ns));
  in.background_keyframe_id = storage::LatestKeyframeId(c, background_scene_id);
  return in;
}

bool SameInputs(const ReanalysisInputs& a, const ReanalysisInputs& b) {
  return a.keyframe_exists == b.keyframe_exists && SameRecords(a.records, b.records) &&
         SameList(a.at_keyframe, b.at_keyframe) && a.background_keyframe_id == b.background_keyframe_id;
}

std::vector<engine::InstanceAtTime> InstancesAtTime(const ReanalysisInputs& in) {
  std::vector<engine::InstanceAtTime> out;
  for (std::size_t i = 0; i < in.records.size(); ++i) {
    out.push_back({in.records[i].id, Vec(in.records[i].extent), PointOf(in.at_keyframe[i])});
  }
  return out;
}

std::vector<EventView> WriteChangeSet(storage::Connection& c, const std::string& map, const engine::ChangeSet& changes,
                                      std::map<std::int64_t, storage::InstanceRecord> records, std::int64_t now_ns) {
  std::vector<std::int64_t> segment_ids, instance_ids, event_ids;
  for (const engine::SegmentToStore& s : changes.segments) {
    storage::SegmentRecord r;
    r.map_id = map;
    r.keyframe_id = s.keyframe_id;
    for (int k = 0; k < 3; ++k) r.centroid[k] = s.segment.centroid_m[k], r.min[k] = s.segment.min_m[k], r.max[k] = s.segment.max_m[k];
    r.points = s.segment.points;
    r.sample = EncodePoints(s.segment.sample_m);
    segment_ids.push_back(storage::InsertSegment(c, r));
  }
  for (const engine::NewInstance& n : changes.new_instances) {
    storage::InstanceRecord r;
    r.map_id = map;
    r.status = n.present ? "present" : "absent";
    for (int k = 0; k < 3; ++k) r.position[k] = n.position_m[k], r.extent[k] = n.extent_m[k];
    r.last_seen_ns = n.last_seen_ns;
    r.last_scene_id = n.last_scene_id;
    r.sample = EncodePoints(n.sample_m);
    r.created_ns = r.updated_ns = now_ns;
    instance_ids.push_back(storage::InsertInstance(c, r));
  }
  for (const engine::NewEvent& e : changes.events) {
    event_ids.push_back(storage::InsertEvent(c, EventRecordOf(map, e, now_ns, segment_ids, instance_ids, event_ids)));
  }
  for (const engine::InstanceUpdate& u : changes.updates) {
    const auto it = records.find(u.instance.id);
    if (u.instance.is_new() || it == records.end()) throw Error(ErrorCode::kInternal, "a change set updates an unknown instance");
    storage::InstanceRecord& r = it->second;
    if (u.present) r.status = *u.present ? "present" : "absent";
    if (u.position_m) for (int k = 0; k < 3; ++k) r.position[k] = (*u.position_m)[k];
    if (u.extent_m) for (int k = 0; k < 3; ++k) r.extent[k] = (*u.extent_m)[k];
    if (u.last_seen_ns) r.last_seen_ns = *u.last_seen_ns;
    if (u.last_scene_id) r.last_scene_id = *u.last_scene_id;
    if (u.sample_m) r.sample = EncodePoints(*u.sample_m);
    if (u.touch) r.updated_ns = now_ns;
    storage::UpdateInstance(c, r);
  }
  for (const engine::HistoryRow& h : changes.history) {
    storage::HistoryRecord r;
    r.instance_id = Resolve(h.instance, instance_ids);
    r.stamp_ns = h.stamp_ns;
    r.present = h.present;
    for (int k = 0; k < 3; ++k) r.position[k] = h.position_m[k];
    if (h.event) r.event_id = Resolve(*h.event, event_ids);
    storage::AppendHistory(c, r);
  }
  std::vector<EventView> out;
  for (std::int64_t id : event_ids) out.push_back(ToView(*storage::FindEvent(c, map, id)));
  return out;
}

bool Empty(const engine::ChangeSet& c) {
  return c.segments.empty() && c.new_instances.empty() && c.events.empty() && c.updates.empty() && c.history.empty();
}

}  // namespace anchordb::services::events_internal
