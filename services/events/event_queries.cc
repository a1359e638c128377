// Events, instances, labels from dialog and operators, the where-is question, keyframe pins and re-analysis.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "services/events/event_service.h"
#include "engine/events/placement.h"
#include "schema/error.h"
#include "storage/blob_codec.h"
#include "storage/furniture_repository.h"
#include "storage/scene_repository.h"

namespace anchordb::services {
namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Json Vec3(const double* v) { return {v[0], v[1], v[2]}; }

void RequireMap(storage::Connection& c, const std::string& map) {
  if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
}

// Lowercase, trimmed, inner whitespace collapsed; refuses empty and overlong labels.
std::string NormaliseLabel(const std::string& raw, std::size_t max_length, const std::string& field) {
  std::string out;
  bool space = false;
  for (unsigned char ch : raw) {
    if (std::isspace(ch)) {
      space = !out.empty();
      continue;
    }
    if (ch < 0x20) throw Error(ErrorCode::kInvalidArgument, "labels must not contain control characters", field);
    if (space) out.push_back(' '), space = false;
    out.push_back(static_cast<char>(std::tolower(ch)));
  }
  if (out.empty()) throw Error(ErrorCode::kUnprocessable, "label must not be empty", field);
  if (out.size() > max_length) throw Error(ErrorCode::kUnprocessable, "label is longer than " + std::to_string(max_length) + " characters", field);
  return out;
}

Json Distribution(const std::string& labels_json) {
  const Json w = Json::parse(labels_json);
  double sum = 0;
  for (auto it = w.begin(); it != w.end(); ++it) sum += it.value().get<double>();
  Json out = Json::object();
  for (auto it = w.begin(); it != w.end(); ++it) out[it.key()] = sum > 0 ? it.value().get<double>() / sum : 0.0;
  return out;
}

double LabelProbability(const std::string& labels_json, const std::string& label) {
  const Json d = Distribution(labels_json);
  return d.contains(label) ? d[label].get<double>() : 0.0;
}

storage::InstanceRecord RequireInstance(storage::Connection& c, const std::string& map, std::int64_t id) {
  RequireMap(c, map);
  auto r = storage::FindInstance(c, map, id, false);
  if (!r) throw Error(ErrorCode::kNotFound, "instance " + std::to_string(id) + " does not exist in map '" + map + "'", "instance");
  return *r;
}

std::string Source(const Json& body) {
  const std::string source = json::OptionalString(body, "source", 16).value_or("dialog");
  if (source != "dialog" && source != "operator") throw Error(ErrorCode::kInvalidArgument, "source must be dialog or operator", "source");
  return source;
}

}  // namespace

Json EventService::EventJson(const storage::EventRecord& e) const {
  Json evidence = Json::array();
  for (const auto& k : e.evidence) evidence.push_back({{"keyframe", k.keyframe_id}, {"role", k.role}});
  return {{"id", e.id}, {"type", e.type}, {"detection", e.detection}, {"stamp_ns", e.stamp_ns},
          {"scene", e.scene_id ? Json(*e.scene_id) : Json(nullptr)},
          {"action_layer", e.action_layer ? Json(*e.action_layer) : Json(nullptr)},
          {"instance", e.instance_id ? Json(*e.instance_id) : Json(nullptr)},
          {"segment", e.segment_id ? Json(*e.segment_id) : Json(nullptr)},
          {"label", e.label ? Json(*e.label) : Json(nullptr)}, {"explanation", e.explanation},
          {"details", Json::parse(e.details_json)}, {"evidence", evidence}};
}

Json EventService::InstanceJson(const storage::InstanceRecord& r) const {
  return {{"id", r.id}, {"kind", r.kind}, {"status", r.status}, {"labels", Distribution(r.labels_json)},
          {"label_locked", r.label_locked}, {"pinned", r.pinned}, {"position_m", Vec3(r.position)},
          {"extent_m", Vec3(r.extent)}, {"yaw_rad", r.yaw_rad}, {"last_seen_ns", r.last_seen_ns},
          {"last_scene", r.last_scene_id ? Json(*r.last_scene_id) : Json(nullptr)}, {"created_ns", r.created_ns},
          {"updated_ns", r.updated_ns}};
}

Json EventService::ListEvents(const std::string& map, const storage::EventFilter& filter) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    Json list = Json::array();
    const auto events = storage::ListEvents(c, map, filter);
    for (const auto& e : events) list.push_back(EventJson(e));
    Json out = {{"events", list}};
    if (static_cast<int>(events.size()) == filter.limit) out["next_after"] = events.back().id;
    return out;
  });
}

Json EventService::GetEvent(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    const auto e = storage::FindEvent(c, map, id);
    if (!e) throw Error(ErrorCode::kNotFound, "event " + std::to_string(id) + " does not exist in map '" + map + "'", "event");
    return EventJson(*e);
  });
}

Json EventService::LabelInstance(const std::string& map, std::int64_t id, const Json& body) {
  json::RejectUnknownKeys(body, {"label", "source"});
  const std::string label = NormaliseLabel(json::RequireString(body, "label", 4096), settings_.max_label_length, "label");
  const std::string source = Source(body);
  std::lock_guard<std::mutex> lock(analysis_mutex_);
  return store_.Write([&](storage::Connection& c) {
    storage::InstanceRecord r = RequireInstance(c, map, id);
    if (r.status == "deleted") throw Error(ErrorCode::kConflict, "instance " + std::to_string(id) + " was deleted by an operator", "instance");
    if (r.label_locked && source != "operator") {
      throw Error(ErrorCode::kConflict, "instance " + std::to_string(id) + " was labelled by an operator; only an operator relabels it", "label");
    }
    Json weights = Json::parse(r.labels_json);
    if (source == "operator") {
      weights = Json{{label, 1.0}};
      r.label_locked = true;
    } else {
      weights[label] = weights.value(label, 0.0) + 1.0;
    }
    r.labels_json = weights.dump();
    r.updated_ns = NowNs();
    storage::UpdateInstance(c, r);
    storage::EventRecord e;
    e.map_id = map;
    e.type = "labelled";
    e.detection = source;
    e.stamp_ns = r.updated_ns;
    e.instance_id = id;
    e.label = label;
    e.created_ns = r.updated_ns;
    e.explanation = source == "operator" ? "an operator set the label; automatic processing will not change it"
                                         : "a person named the object in dialog";
    e.details_json = Json{{"labels", Distribution(r.labels_json)}}.dump();
    e.id = storage::InsertEvent(c, e);
    return Json{{"instance", InstanceJson(r)}, {"event", EventJson(*storage::FindEvent(c, map, e.id))}};
  });
}

Json EventService::LabelEvent(const std::string& map, std::int64_t id, const Json& body) {
  const auto e = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::FindEvent(c, map, id);
  });
  if (!e) throw Error(ErrorCode::kNotFound, "event " + std::to_string(id) + " does not exist in map '" + map + "'", "event");
  if (!e->instance_id) throw Error(ErrorCode::kUnprocessable, "event " + std::to_string(id) + " concerns no instance", "event");
  Json out = LabelInstance(map, *e->instance_id, body);
  out["labelled_event"] = id;
  return out;
}

Json EventService::CreateInstance(const std::string& map, const Json& body) {
  json::RejectUnknownKeys(body, {"kind", "label", "position", "extent", "yaw_rad", "stamp"});
  const std::string kind = json::OptionalString(body, "kind", 16).value_or("furniture");
  if (kind != "furniture" && kind != "object") throw Error(ErrorCode::kInvalidArgument, "kind must be furniture or object", "kind");
  const std::string label = NormaliseLabel(json::RequireString(body, "label", 4096), settings_.max_label_length, "label");
  storage::InstanceRecord r;
  r.map_id = map;
  r.kind = kind;
  r.labels_json = Json{{label, 1.0}}.dump();
  r.label_locked = true;  // entered by an operator
  const auto vec3 = [&](const char* key, double* out, bool required) {
    if (!body.contains(key)) {
      if (required) throw Error(ErrorCode::kInvalidArgument, std::string(key) + " is required: [x, y, z]", key);
      return;
    }
    const Json& v = body[key];
    if (!v.is_array() || v.size() != 3) throw Error(ErrorCode::kInvalidArgument, std::string(key) + " must be [x, y, z]", key);
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number() || !std::isfinite(v[k].get<double>())) throw Error(ErrorCode::kInvalidArgument, std::string(key) + " must hold finite numbers", key);
      out[k] = v[k].get<double>();
    }
  };
  vec3("position", r.position, true);
  vec3("extent", r.extent, false);
  for (double e : r.extent) if (e < 0) throw Error(ErrorCode::kUnprocessable, "extent must not be negative", "extent");
  r.yaw_rad = json::FiniteNumberOr(body, "yaw_rad", 0.0);
  r.last_seen_ns = body.contains("stamp") ? json::AsStampNs(body["stamp"], "stamp") : NowNs();
  r.created_ns = r.updated_ns = NowNs();
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    r.id = storage::InsertInstance(c, r);
    storage::AppendHistory(c, {r.id, 0, r.last_seen_ns, true, {r.position[0], r.position[1], r.position[2]}, std::nullopt});
    return InstanceJson(r);
  });
}

Json EventService::ListInstances(const std::string& map, const std::optional<std::string>& label,
                                 const storage::InstanceFilter& f) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::InstanceFilter filter = f;
    if (label) filter.label = NormaliseLabel(*label, settings_.max_label_length, "label");
    Json list = Json::array();
    const auto records = storage::ListInstances(c, map, filter, false);
    for (const auto& r : records) list.push_back(InstanceJson(r));
    Json out = {{"instances", list}};
    if (static_cast<int>(records.size()) == f.limit) out["next_after"] = records.back().id;
    return out;
  });
}

Json EventService::GetInstance(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) { return InstanceJson(RequireInstance(c, map, id)); });
}

Json EventService::History(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) {
    const auto r = RequireInstance(c, map, id);
    Json list = Json::array();
    for (const auto& h : storage::ListHistory(c, id)) {
      list.push_back({{"seq", h.seq}, {"stamp_ns", h.stamp_ns}, {"present", h.present}, {"position_m", Vec3(h.position)},
                      {"event", h.event_id ? Json(*h.event_id) : Json(nullptr)}});
    }
    return Json{{"instance", InstanceJson(r)}, {"history", list}};
  });
}

Json EventService::PinInstance(const std::string& map, std::int64_t id, bool pinned) {
  return store_.Write([&](storage::Connection& c) {
    auto r = RequireInstance(c, map, id);
    r.pinned = pinned;
    r.updated_ns = NowNs();
    storage::UpdateInstance(c, r);
    return InstanceJson(r);
  });
}

Json EventService::DeleteInstance(const std::string& map, std::int64_t id) {
  std::lock_guard<std::mutex> lock(analysis_mutex_);
  return store_.Write([&](storage::Connection& c) {
    auto r = RequireInstance(c, map, id);
    r.status = "deleted";
    r.status_locked = true;  // never revived by later matching or the lost-key rule
    r.updated_ns = NowNs();
    storage::UpdateInstance(c, r);
    return InstanceJson(r);
  });
}

Json EventService::Where(const std::string& map, const std::string& raw_label, std::optional<std::int64_t> at_ns) {
  const std::string label = NormaliseLabel(raw_label, settings_.max_label_length, "label");
  const std::int64_t now = NowNs();
  if (at_ns && *at_ns > now) throw Error(ErrorCode::kUnprocessable, "at lies in the future; where answers for the past and now", "at");
  // One read lease for the answer and the furniture it may be placed against.
  std::vector<engine::FurniturePiece> pieces;
  engine::grounding::Viewpoint viewer;  // for plain geometry: the camera that saw the object last (else the origin)
  std::optional<std::int64_t> graph;    // the map's newest furniture graph
  Json out = store_.Read([&](storage::Connection& c) -> Json {
    RequireMap(c, map);
    storage::InstanceFilter f;
    f.kind = "object";
    f.label = label;
    f.limit = 100000;
    std::optional<storage::InstanceRecord> best;
    std::optional<storage::HistoryRecord> best_h;
    double best_p = 0.0;
    for (const auto& r : storage::ListInstances(c, map, f, false)) {
      const double p = LabelProbability(r.labels_json, label);
      if (p <= 0.0) continue;
      const auto h = storage::HistoryAt(c, r.id, at_ns.value_or(std::numeric_limits<std::int64_t>::max()));
      if (!h) continue;
      if (!best || p > best_p + 1e-9 || (std::abs(p - best_p) <= 1e-9 && h->stamp_ns > best_h->stamp_ns)) best = r, best_h = h, best_p = p;
    }
    if (!best) {
      throw Error(ErrorCode::kNotFound, "nothing labelled '" + label + "' is known" + (at_ns ? " at that time" : ""), "label");
    }
    Json evidence = Json::array();
    std::string how = "observed";
    if (best_h->event_id) {
      if (const auto e = storage::FindEvent(c, map, *best_h->event_id)) {
        for (const auto& k : e->evidence) evidence.push_back({{"keyframe", k.keyframe_id}, {"role", k.role}, {"event", e->id}});
        how = e->type == "moved" ? "inferred" : e->detection;
      }
    }
    if (best->last_scene_id) {
      if (const auto scene = storage::FindScene(c, map, *best->last_scene_id, false)) {
        const Pose3 pose = json::AsPose3(Json::parse(scene->pose_json), "pose");
        const Eigen::Vector3d axis = pose.orientation * Eigen::Vector3d::UnitZ();  // the optical axis in the map
        viewer.position_m = pose.position_m.head<2>();
        viewer.heading_rad = std::atan2(axis.y(), axis.x());
      }
    }
    graph = storage::NewestFurnitureGraphId(c, map);
    // Furniture an operator entered, for plain-geometry placement when the map has no furniture graph.
    storage::InstanceFilter furniture;
    furniture.kind = "furniture";
    furniture.limit = 10000;
    for (const auto& r : storage::ListInstances(c, map, furniture, false)) {
      const Json d = Distribution(r.labels_json);
      pieces.push_back({std::to_string(r.id), d.empty() ? "furniture" : d.begin().key(), {r.position[0], r.position[1]},
                        {r.extent[0], r.extent[1]}, r.yaw_rad});
    }
    // Confidence: how sure the label is, times how the position is known (seen, merged from another visit, inferred).
    const double position_confidence = how == "observed" ? 0.95 : how == "meanwhile" ? 0.85 : how == "inferred" ? 0.7 : 0.8;
    return Json{{"label", label}, {"instance", best->id}, {"present", best_h->present},
                {"position_m", Vec3(best_h->position)}, {"seen_ns", best_h->stamp_ns}, {"how", how},
                {"evidence", evidence}, {"confidence", best_p * position_confidence}, {"label_probability", best_p},
                {"at_ns", at_ns ? Json(*at_ns) : Json(nullptr)}};
  });
  const Eigen::Vector3d p(out["position_m"][0].get<double>(), out["position_m"][1].get<double>(), out["position_m"][2].get<double>());
  std::optional<Json> place;
  if (const auto placed = furniture_ && graph ? furniture_->Place(map, p, graph) : std::nullopt) {
    place = Json{{"graph", placed->graph}, {"furniture", placed->furniture}, {"category", placed->category},
                 {"name", placed->name}, {"relation", placed->relation},
                 {"frame", placed->frame ? Json(*placed->frame) : Json(nullptr)}, {"gap_m", placed->gap_m},
                 {"phrase", placed->phrase}};
  }
  if (!place) {  // plain geometry: the nearest furniture instance an operator entered
    const std::vector<engine::FurniturePiece>& list = pieces;
    if (!list.empty()) {
      const engine::Placement placed = engine::PlaceObject(p, list, viewer);
      const auto& piece = list[static_cast<std::size_t>(placed.piece)];
      place = Json{{"furniture_instance", std::stoll(piece.id)}, {"name", piece.name}, {"gap_m", placed.gap_m},
                   {"relation", placed.on ? "on" : engine::grounding::RelationId(placed.relative)}, {"frame", "geometry"},
                   {"phrase", placed.on ? "on the " + piece.name
                                        : std::string(engine::grounding::RelationPhrase(placed.relative)) + " the " + piece.name}};
    }
  }
  std::string where = place ? (*place)["phrase"].get<std::string>()
                            : "at (" + std::to_string(p.x()).substr(0, 5) + ", " + std::to_string(p.y()).substr(0, 5) + ") in the map";
  out["placement"] = place ? *place : Json(nullptr);
  const bool present = out["present"].get<bool>();
  // English agreement by the label's last letter ("keys are", "the mug is"): good enough for spoken answers.
  const bool plural = label.back() == 's';
  const std::string is = at_ns ? (plural ? " were " : " was ") : (plural ? " are " : " is ");
  out["sentence"] = present ? "The " + label + is + where + "."
                            : "The " + label + (plural ? " were" : " was") + " last seen " + where + "; " +
                                  (plural ? "they were" : "it was") + " taken away and " + (plural ? "have" : "has") +
                                  " not been seen since.";
  return out;
}

Json EventService::PinKeyframe(const std::string& map, std::int64_t id, bool pinned) {
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    if (!storage::SetKeyframePinned(c, map, id, pinned)) {
      throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(id) + " does not exist in map '" + map + "'", "keyframe");
    }
    return Json{{"keyframe", id}, {"pinned", pinned}};
  });
}

Json EventService::SetKeyframeRelevance(const std::string& map, std::int64_t id, const Json& body) {
  json::RejectUnknownKeys(body, {"relevance"});
  const double relevance = json::RequireFiniteNumber(body, "relevance");
  if (relevance < 0.0 || relevance > 1.0) throw Error(ErrorCode::kUnprocessable, "relevance must be in [0, 1]", "relevance");
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    if (!storage::SetKeyframeRelevance(c, map, id, relevance)) {
      throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(id) + " does not exist in map '" + map + "'", "keyframe");
    }
    return Json{{"keyframe", id}, {"relevance", relevance}};
  });
}

}  // namespace anchordb::services
