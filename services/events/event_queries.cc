// Events, instances, labels from dialog and operators, the where-is question and keyframe pins (see event_service.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/classification/object_labels.h"
#include "engine/events/labels.h"
#include "engine/events/placement.h"
#include "engine/events/sentences.h"
#include "engine/events/where.h"
#include "schema/error.h"
#include "services/common/stored_pose.h"
#include "services/events/event_details.h"
#include "services/events/event_records_internal.h"
#include "services/events/event_service.h"
#include "services/furniture/furniture_service.h"
#include "storage/furniture_repository.h"
#include "storage/scene_repository.h"

namespace anchordb::services {

using namespace events_internal;

namespace {

std::string NotFoundText(const char* what, std::int64_t id, const std::string& map) {
  return std::string(what) + " " + std::to_string(id) + " does not exist in map '" + map + "'";
}

EventView RequireEvent(storage::Connection& c, const std::string& map, std::int64_t id) {
  RequireMap(c, map);
  const auto e = storage::FindEvent(c, map, id);
  if (!e) throw Error(ErrorCode::kNotFound, NotFoundText("event", id, map), "event");
  return ToView(*e);
}

}  // namespace

EventPage EventService::ListEvents(const std::string& map, const EventQuery& query) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    EventPage out;
    for (const auto& e : storage::ListEvents(c, map, query)) out.events.push_back(ToView(e));
    if (static_cast<int>(out.events.size()) == query.limit) out.next_after = out.events.back().id;
    return out;
  });
}

std::int64_t EventService::LatestEventId(const std::string& map) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::MaxEventId(c, map);
  });
}

EventView EventService::GetEvent(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) { return RequireEvent(c, map, id); });
}

LabelResult EventService::LabelInstance(const std::string& map, std::int64_t id, const LabelRequest& request) {
  const std::string label = engine::NormaliseLabel(request.label, settings_.max_label_length, "label");
  const bool from_operator = request.source == LabelSource::kOperator;
  // No analysis mutex: the edit is one write transaction, and an analysis running meanwhile sees the map's instance
  // count changed in its write and starts again, so a label never waits for a keyframe's analysis (seconds).
  return store_.Write([&](storage::Connection& c) {
    storage::InstanceRecord r = RequireInstance(c, map, id);
    if (r.status == "deleted") throw Error(ErrorCode::kConflict, "instance " + std::to_string(id) + " was deleted by an operator", "instance");
    if (r.label_locked && !from_operator) {
      throw Error(ErrorCode::kConflict, "instance " + std::to_string(id) + " was labelled by an operator; only an operator relabels it", "label");
    }
    const engine::LabelWeights weights = engine::AddLabel(r.labels, label, from_operator);
    r.label_locked = r.label_locked || from_operator;
    r.labels = weights;
    r.updated_ns = clock_.NowNs();
    storage::UpdateInstance(c, r);
    const std::int64_t event = InsertLabelledEvent(c, map, id, label, from_operator ? "operator" : "dialog", r.updated_ns,
                                                   engine::LabelledExplanation(from_operator), engine::LabelDistribution(weights));
    return LabelResult{ViewOf(c, r), ToView(*storage::FindEvent(c, map, event)), std::nullopt};
  });
}

LabelResult EventService::LabelEvent(const std::string& map, std::int64_t event_id, const LabelRequest& request) {
  const EventView e = store_.Read([&](storage::Connection& c) { return RequireEvent(c, map, event_id); });
  if (!e.instance_id) throw Error(ErrorCode::kUnprocessable, "event " + std::to_string(event_id) + " concerns no instance", "event");
  LabelResult out = LabelInstance(map, *e.instance_id, request);
  out.labelled_event = event_id;
  return out;
}

EventView EventService::DeleteEvent(const std::string& map, std::int64_t event_id) {  // no analysis mutex (see above)
  return store_.Write([&](storage::Connection& c) {
    EventView before = RequireEvent(c, map, event_id);
    storage::DeleteEvent(c, map, event_id);
    return before;
  });
}

InstanceView EventService::CreateInstance(const std::string& map, const CreateInstanceRequest& request) {
  const std::string label = engine::NormaliseLabel(request.label, settings_.max_label_length, "label");
  if ((request.extent_m.array() < 0).any()) throw Error(ErrorCode::kUnprocessable, "extent must not be negative", "extent");
  storage::InstanceRecord r;
  r.map_id = map;
  r.kind = request.kind == InstanceKind::kObject ? "object" : "furniture";
  r.labels = {{label, 1.0}};
  r.label_locked = true;  // entered by an operator
  for (int k = 0; k < 3; ++k) r.position[k] = request.position_m[k], r.extent[k] = request.extent_m[k];
  r.yaw_rad = request.yaw_rad;
  r.created_ns = r.updated_ns = clock_.NowNs();
  r.last_seen_ns = request.stamp_ns.value_or(r.created_ns);
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    r.id = storage::InsertInstance(c, r);
    storage::AppendHistory(c, {r.id, 0, r.last_seen_ns, true, {r.position[0], r.position[1], r.position[2]}, std::nullopt});
    return ToView(r);
  });
}

InstancePage EventService::ListInstances(const std::string& map, const InstanceQuery& query) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::InstanceFilter filter;
    if (query.label) filter.label = engine::NormaliseLabel(*query.label, settings_.max_label_length, "label");
    filter.label_from_classifier = true;  // the labels the listing shows: a classifier's for an object nobody named
    filter.kind = query.kind;
    filter.status = query.status;
    filter.after_id = query.after_id;
    filter.limit = query.limit;
    InstancePage out;
    // Each listed instance's classification by its key: the cost follows the page, not the map's classified objects.
    for (const auto& r : storage::ListInstances(c, map, filter, false)) out.instances.push_back(ViewOf(c, r));
    if (static_cast<int>(out.instances.size()) == query.limit) out.next_after = out.instances.back().id;
    return out;
  });
}

InstanceView EventService::GetInstance(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) { return ViewOf(c, RequireInstance(c, map, id)); });
}

InstanceHistory EventService::History(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) {
    InstanceHistory out{ViewOf(c, RequireInstance(c, map, id)), {}};
    for (const auto& h : storage::ListHistory(c, id)) out.history.push_back({h.seq, h.stamp_ns, h.present, Vec(h.position), h.event_id});
    return out;
  });
}

InstanceView EventService::PinInstance(const std::string& map, std::int64_t id, bool pinned) {
  return store_.Write([&](storage::Connection& c) {
    auto r = RequireInstance(c, map, id);
    r.pinned = pinned;
    r.updated_ns = clock_.NowNs();
    storage::UpdateInstance(c, r);
    return ViewOf(c, r);
  });
}

InstanceView EventService::DeleteInstance(const std::string& map, std::int64_t id) {  // no analysis mutex (see above)
  return store_.Write([&](storage::Connection& c) {
    auto r = RequireInstance(c, map, id);
    r.status = "deleted";
    r.status_locked = true;  // never revived by later matching or the lost-key rule
    r.updated_ns = clock_.NowNs();
    storage::UpdateInstance(c, r);
    return ViewOf(c, r);
  });
}

// The one use of FurnitureService::Place: its answer as a where-is placement (nullopt without a furniture graph).
std::optional<WherePlacement> EventService::GraphPlacement(const std::string& map, const Eigen::Vector3d& p_map,
                                                           std::optional<std::int64_t> graph) {
  if (!furniture_ || !graph) return std::nullopt;
  const std::optional<Placement> place = furniture_->Place(map, p_map, graph);
  if (!place) return std::nullopt;
  WherePlacement out;
  out.graph = place->graph;
  out.furniture = place->furniture;
  out.category = place->category;
  out.name = place->name;
  out.relation = place->relation;
  out.frame = place->frame;
  out.gap_m = place->gap_m;
  out.phrase = place->phrase;
  return out;
}

namespace {

// Where-is candidates: each instance with its label probability and where it was at the time asked (nullopt when the
// probability is not positive or nothing was recorded by then).
struct WhereCandidates {
  std::vector<storage::InstanceRecord> instances;
  std::vector<std::optional<storage::HistoryRecord>> positions;
  std::vector<engine::WhereCandidate> scored;

  void Add(storage::InstanceRecord r, double p, std::optional<storage::HistoryRecord> h) {
    if (p <= 0.0) h.reset();
    scored.push_back({p, h ? std::optional(h->stamp_ns) : std::nullopt});
    positions.push_back(std::move(h));
    instances.push_back(std::move(r));
  }
};

// The second pass, when no person named an object so: the objects a classifier named `label` that nobody named
// otherwise (engine/classification/object_labels.h). Checks the map first (a missing map is its own 404).
WhereCandidates ClassifiedCandidates(storage::Connection& c, const std::string& map, const std::string& label,
                                     std::int64_t at_ns) {
  RequireMap(c, map);
  storage::InstanceFilter f;
  f.kind = "object";
  f.label = label;
  f.label_from_classifier = true;  // only the objects whose classification gives the label a share (in SQL)
  f.limit = 100000;
  WhereCandidates out;
  for (auto& r : storage::ListInstances(c, map, f, false)) {
    const auto k = storage::FindInstanceClassification(c, map, r.id);
    if (!k) continue;  // named by a person, and found by the first pass's rules
    const engine::EffectiveLabels labels = engine::EffectiveObjectLabels(r.labels, r.label_locked,
                                                                        DecodeDistribution(*k));
    if (labels.source != engine::LabelSource::kClassifier) continue;
    const auto p = labels.distribution.find(label);
    if (p == labels.distribution.end()) continue;
    std::optional<storage::HistoryRecord> h = p->second > 0.0 ? storage::HistoryAt(c, r.id, at_ns) : std::nullopt;
    out.Add(std::move(r), p->second, std::move(h));
  }
  return out;
}

// How the answer's position became known (the event that recorded it, with its keyframes) and the camera that saw
// the object last (the viewer of plain-geometry placement; the origin when none did).
void ReadProvenance(storage::Connection& c, const std::string& map, const storage::InstanceRecord& best,
                    const storage::HistoryRecord& h, WhereAnswer& a, std::optional<engine::PositionOrigin>& origin,
                    engine::grounding::Viewpoint& viewer) {
  if (h.event_id) {
    if (const auto e = storage::FindEvent(c, map, *h.event_id)) {
      for (const auto& k : e->evidence) a.evidence.push_back({k.keyframe_id, k.role, e->id});
      origin = engine::PositionOrigin{e->type, e->detection};
    }
  }
  if (best.last_scene_id) {
    if (const auto scene = storage::FindScene(c, map, *best.last_scene_id, false)) {
      const Pose3 pose = StoredPose(*scene);
      const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();  // the optical axis in the map
      viewer.position_m = pose.position_m.head<2>();
      viewer.heading_rad = std::atan2(axis.y(), axis.x());
    }
  }
}

// Plain-geometry placement, for a map without a furniture graph: the nearest furniture instance an operator entered
// or a segmentation found, described as seen by `viewer`.
WherePlacement GeometryPlacement(const std::vector<storage::InstanceRecord>& furniture, const Eigen::Vector3d& p_map,
                                 const engine::grounding::Viewpoint& viewer) {
  std::vector<engine::FurniturePiece> pieces;
  for (const auto& r : furniture) {
    pieces.push_back({std::to_string(r.id), engine::FurnitureName(r.labels), {r.position[0], r.position[1]},
                      {r.extent[0], r.extent[1]}, r.yaw_rad});
  }
  const engine::Placement placed = engine::PlaceObject(p_map, pieces, viewer);
  const engine::FurniturePiece& piece = pieces[static_cast<std::size_t>(placed.piece)];
  const engine::PlacementWords words = engine::DescribePlacement(placed, piece.name);
  WherePlacement g;
  g.furniture_instance = std::stoll(piece.id);
  g.name = piece.name;
  g.gap_m = placed.gap_m;
  g.relation = words.relation;
  g.frame = "geometry";
  g.phrase = words.phrase;
  return g;
}

}  // namespace

// Reads: the objects a person named so, their positions at the time, the map's furniture and its newest graph come
// in one statement (one round trip on PostgreSQL, consistent on its own). The classifier's pass and the provenance
// (the recording event, the last camera) are read after it only when needed: events, their evidence and scenes are
// never changed once written, so reading them a moment later answers the same (a forgotten one is simply absent).
storage::WhereInputs EventService::WhereInputsFor(const std::string& map, const std::string& label,
                                                  std::optional<std::int64_t> at_ns) {
  if (!at_ns && where_cache_.Holds(map, label)) {
    const storage::WhereStamp now = store_.ReadOneStatement([&](storage::Connection& c) { return storage::ReadWhereStamp(c, map); });
    if (auto kept = where_cache_.Find(map, label, now)) return std::move(*kept);
  }
  const std::int64_t at = at_ns.value_or(std::numeric_limits<std::int64_t>::max());
  storage::WhereInputs inputs = store_.ReadOneStatement([&](storage::Connection& c) {
    return storage::ReadWhereInputs(c, map, label, at);
  });
  if (!at_ns) where_cache_.Put(map, label, inputs);
  return inputs;
}

WhereAnswer EventService::Where(const std::string& map, const WhereRequest& request) {
  const std::string label = engine::NormaliseLabel(request.label, settings_.max_label_length, "label");
  const std::optional<std::int64_t> at_ns = request.at_ns;
  if (at_ns && *at_ns > clock_.NowNs()) throw Error(ErrorCode::kUnprocessable, "at lies in the future; where answers for the past and now", "at");
  const std::int64_t at = at_ns.value_or(std::numeric_limits<std::int64_t>::max());
  storage::WhereInputs inputs = WhereInputsFor(map, label, at_ns);
  WhereCandidates found;
  for (auto& r : inputs.labelled) {
    const double p = engine::LabelProbability(r.instance.labels, label);
    found.Add(std::move(r.instance), p, std::move(r.position));
  }
  int chosen = engine::ChooseWhereCandidate(found.scored);
  std::string label_source;
  if (chosen >= 0) {
    label_source = found.instances[static_cast<std::size_t>(chosen)].label_locked ? "operator" : "dialog";
  } else {
    found = store_.Read([&](storage::Connection& c) { return ClassifiedCandidates(c, map, label, at); });
    chosen = engine::ChooseWhereCandidate(found.scored);
    label_source = "classifier";
  }
  if (chosen < 0) throw Error(ErrorCode::kNotFound, "nothing labelled '" + label + "' is known" + (at_ns ? " at that time" : ""), "label");
  const auto k = static_cast<std::size_t>(chosen);
  const storage::InstanceRecord& best = found.instances[k];
  const storage::HistoryRecord& h = *found.positions[k];
  WhereAnswer out;
  std::optional<engine::PositionOrigin> origin;
  engine::grounding::Viewpoint viewer;  // for plain geometry: the camera that saw the object last (else the origin)
  if (h.event_id || best.last_scene_id) {
    store_.Read([&](storage::Connection& c) { ReadProvenance(c, map, best, h, out, origin, viewer); });
  }
  out.label = label;
  out.instance_id = best.id;
  out.present = h.present;
  out.position_m = Vec(h.position);
  out.seen_ns = h.stamp_ns;
  out.how = engine::HowKnown(origin);
  out.label_probability = found.scored[k].label_probability;
  out.label_source = label_source;
  out.confidence = engine::WhereConfidence(out.label_probability, out.how);
  out.at_ns = at_ns;
  out.placement = GraphPlacement(map, out.position_m, inputs.stamp.newest_graph_id);
  if (!out.placement && !inputs.furniture.empty()) out.placement = GeometryPlacement(inputs.furniture, out.position_m, viewer);
  const std::string where = out.placement ? out.placement->phrase : engine::MapPositionPhrase(out.position_m);
  out.sentence = engine::WhereSentence(label, where, out.present, at_ns.has_value());
  return out;
}

KeyframePinned EventService::PinKeyframe(const std::string& map, std::int64_t id, bool pinned) {
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    if (!storage::SetKeyframePinned(c, map, id, pinned)) throw Error(ErrorCode::kNotFound, NotFoundText("keyframe", id, map), "keyframe");
    return KeyframePinned{id, pinned};
  });
}

KeyframeRelevance EventService::SetKeyframeRelevance(const std::string& map, std::int64_t id, double relevance) {
  if (relevance < 0.0 || relevance > 1.0) throw Error(ErrorCode::kUnprocessable, "relevance must be in [0, 1]", "relevance");
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    if (!storage::SetKeyframeRelevance(c, map, id, relevance)) throw Error(ErrorCode::kNotFound, NotFoundText("keyframe", id, map), "keyframe");
    return KeyframeRelevance{id, relevance};
  });
}

}  // namespace anchordb::services
