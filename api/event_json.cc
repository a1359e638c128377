// JSON of the event service's requests and results (see event_json.h).
#include "api/event_json.h"
#include "api/request_limits.h"

#include <cmath>

#include "api/route_params.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

Json Vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

template <typename T>
Json OrNull(const std::optional<T>& v) {
  return v ? Json(*v) : Json(nullptr);
}

// [x, y, z] of finite numbers at `key`; nullopt when absent and not required.
std::optional<Eigen::Vector3d> Vector3At(const Json& body, const char* key, bool required) {
  if (!body.contains(key)) {
    if (required) throw Error(ErrorCode::kInvalidArgument, std::string(key) + " is required: [x, y, z]", key);
    return std::nullopt;
  }
  const Json& v = body[key];
  if (!v.is_array() || v.size() != 3) throw Error(ErrorCode::kInvalidArgument, std::string(key) + " must be [x, y, z]", key);
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !std::isfinite(v[k].get<double>())) {
      throw Error(ErrorCode::kInvalidArgument, std::string(key) + " must hold finite numbers", key);
    }
    out[k] = v[k].get<double>();
  }
  return out;
}

Json SegmentJson(const engine::SegmentSummary& s) {
  return {{"centroid_m", Vec3(s.centroid_m)}, {"extent_m", Vec3(s.extent_m)}, {"points", s.points}};
}

// {key: [item...], "next_after" when the page is full}.
template <typename T, typename F>
Json PageJson(const char* key, const std::vector<T>& items, const std::optional<std::int64_t>& next_after, F item_json) {
  Json list = Json::array();
  for (const auto& item : items) list.push_back(item_json(item));
  Json out = {{key, list}};
  if (next_after) out["next_after"] = *next_after;
  return out;
}

Json PlacementJson(const WherePlacement& p) {
  if (p.furniture_instance) {
    return {{"furniture_instance", *p.furniture_instance}, {"name", p.name}, {"gap_m", p.gap_m}, {"relation", p.relation},
            {"frame", OrNull(p.frame)}, {"phrase", p.phrase}};
  }
  return {{"graph", OrNull(p.graph)}, {"furniture", p.furniture}, {"category", p.category}, {"name", p.name},
          {"gap_m", p.gap_m}, {"relation", p.relation}, {"frame", OrNull(p.frame)}, {"phrase", p.phrase}};
}

}  // namespace

EventQuery ParseEventQuery(const httplib::Request& req) {
  EventQuery f;
  f.since_ns = QueryTime(req, "since");
  f.until_ns = QueryTime(req, "until");
  f.type = QueryChoice(req, "type", {"added", "removed", "moved", "labelled"});
  if (req.has_param("instance")) f.instance_id = QueryInteger(req, "instance", 0, 1, INT64_MAX);
  if (req.has_param("scene")) f.scene_id = QueryInteger(req, "scene", 0, 1, INT64_MAX);
  f.after_id = QueryInteger(req, "after", 0, 0, INT64_MAX);
  f.limit = static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000));
  return f;
}

InstanceQuery ParseInstanceQuery(const httplib::Request& req) {
  InstanceQuery q;
  q.kind = QueryChoice(req, "kind", {"object", "furniture"});
  q.status = QueryChoice(req, "status", {"present", "absent", "deleted"});
  q.after_id = QueryInteger(req, "after", 0, 0, INT64_MAX);
  q.limit = static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000));
  q.label = QueryString(req, "label", limits::kLabelLength);
  return q;
}

WhereRequest ParseWhereRequest(const httplib::Request& req) {
  const auto label = QueryString(req, "label", limits::kLabelLength);
  if (!label) throw Error(ErrorCode::kInvalidArgument, "label is required", "label");
  return {*label, QueryTime(req, "at")};
}

LabelRequest ParseLabelRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"label", "source"});
  LabelRequest r;
  r.label = json::RequireString(body, "label", limits::kLabelLength);
  const std::string source = json::OptionalString(body, "source", limits::kWordLength).value_or("dialog");
  if (source != "dialog" && source != "operator") throw Error(ErrorCode::kInvalidArgument, "source must be dialog or operator", "source");
  r.source = source == "operator" ? LabelSource::kOperator : LabelSource::kDialog;
  return r;
}

CreateInstanceRequest ParseCreateInstanceRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"kind", "label", "position", "extent", "yaw_rad", "stamp"});
  CreateInstanceRequest r;
  const std::string kind = json::OptionalString(body, "kind", limits::kWordLength).value_or("furniture");
  if (kind != "furniture" && kind != "object") throw Error(ErrorCode::kInvalidArgument, "kind must be furniture or object", "kind");
  r.kind = kind == "object" ? InstanceKind::kObject : InstanceKind::kFurniture;
  r.label = json::RequireString(body, "label", limits::kLabelLength);
  r.position_m = *Vector3At(body, "position", true);
  r.extent_m = Vector3At(body, "extent", false).value_or(Eigen::Vector3d::Zero());
  r.yaw_rad = json::FiniteNumberOr(body, "yaw_rad", 0.0);
  if (body.contains("stamp")) r.stamp_ns = json::AsStampNs(body["stamp"], "stamp");
  return r;
}

double ParseRelevance(const Json& body) {
  json::RejectUnknownKeys(body, {"relevance"});
  return json::RequireFiniteNumber(body, "relevance");
}

ReanalyseRequest ParseReanalyseRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"scene"});
  ReanalyseRequest r;
  if (body.contains("scene")) {
    if (!body["scene"].is_number_integer()) throw Error(ErrorCode::kInvalidArgument, "scene must be an integer id", "scene");
    r.scene_id = body["scene"].get<std::int64_t>();
  }
  return r;
}

namespace {

// {"segment": {centroid_m, extent_m, points}, "from_m", "size_similarity", "removal_event", "visibility":
// {confirmed, seen_through, hidden, unmeasured, outside}, "background_scene", "labels"}, each part present when it
// applies (the keys the stored JSON document of schemas before 0020 had).
Json EventDetailsJson(const EventDetails& d) {
  Json j = Json::object();
  if (d.segment) {
    j["segment"] = {{"centroid_m", Vec3(d.segment->centroid_m)}, {"extent_m", Vec3(d.segment->extent_m)},
                    {"points", d.segment->points}};
  }
  if (d.move) {
    j["from_m"] = Vec3(d.move->from_m);
    j["size_similarity"] = d.move->size_similarity;
    j["removal_event"] = d.move->removal_event ? Json(*d.move->removal_event) : Json(nullptr);
  }
  if (d.visibility) {
    const engine::Visibility& v = *d.visibility;
    j["visibility"] = {{"confirmed", v.confirmed}, {"seen_through", v.seen_through}, {"hidden", v.hidden},
                       {"unmeasured", v.unmeasured}, {"outside", v.outside}};
  }
  if (d.background_scene) j["background_scene"] = *d.background_scene;
  if (d.labels) j["labels"] = *d.labels;
  return j;
}

}  // namespace

Json EventJson(const EventView& e) {
  Json evidence = Json::array();
  for (const auto& k : e.evidence) evidence.push_back({{"keyframe", k.keyframe_id}, {"role", k.role}});
  return {{"id", e.id}, {"type", e.type}, {"detection", e.detection}, {"stamp_ns", e.stamp_ns},
          {"scene", OrNull(e.scene_id)}, {"action_layer", OrNull(e.action_layer)}, {"instance", OrNull(e.instance_id)},
          {"segment", OrNull(e.segment_id)}, {"label", OrNull(e.label)}, {"explanation", e.explanation},
          {"details", EventDetailsJson(e.details)}, {"evidence", evidence}};
}

Json EventPageJson(const EventPage& page) { return PageJson("events", page.events, page.next_after, EventJson); }

Json InstanceJson(const InstanceView& r) {
  Json classification = nullptr;
  if (r.classification) {
    const auto& k = *r.classification;
    classification = {{"classifier", k.classifier}, {"label", k.label}, {"distribution", Json(k.distribution)},
                      {"segment", OrNull(k.segment_id)}, {"keyframe", OrNull(k.keyframe_id)}, {"stamp_ns", k.stamp_ns}};
  }
  return {{"id", r.id}, {"kind", r.kind}, {"status", r.status}, {"labels", Json(r.labels)},
          {"label_source", r.label_source}, {"classification", classification}, {"label_locked", r.label_locked}, {"pinned", r.pinned}, {"position_m", Vec3(r.position_m)},
          {"extent_m", Vec3(r.extent_m)}, {"yaw_rad", r.yaw_rad}, {"last_seen_ns", r.last_seen_ns},
          {"last_scene", OrNull(r.last_scene_id)}, {"created_ns", r.created_ns}, {"updated_ns", r.updated_ns}};
}

Json InstancePageJson(const InstancePage& page) { return PageJson("instances", page.instances, page.next_after, InstanceJson); }

Json HistoryJson(const InstanceHistory& h) {
  Json list = Json::array();
  for (const auto& e : h.history) {
    list.push_back({{"seq", e.seq}, {"stamp_ns", e.stamp_ns}, {"present", e.present}, {"position_m", Vec3(e.position_m)},
                    {"event", OrNull(e.event_id)}});
  }
  return {{"instance", InstanceJson(h.instance)}, {"history", list}};
}

Json LabelResultJson(const LabelResult& r) {
  Json out = {{"instance", InstanceJson(r.instance)}, {"event", EventJson(r.event)}};
  if (r.labelled_event) out["labelled_event"] = *r.labelled_event;
  return out;
}

Json WhereJson(const WhereAnswer& a) {
  Json evidence = Json::array();
  for (const auto& k : a.evidence) evidence.push_back({{"keyframe", k.keyframe_id}, {"role", k.role}, {"event", k.event_id}});
  return {{"label", a.label}, {"instance", a.instance_id}, {"present", a.present}, {"position_m", Vec3(a.position_m)},
          {"seen_ns", a.seen_ns}, {"how", a.how}, {"evidence", evidence}, {"confidence", a.confidence},
          {"label_probability", a.label_probability}, {"label_source", a.label_source}, {"at_ns", OrNull(a.at_ns)},
          {"placement", a.placement ? PlacementJson(*a.placement) : Json(nullptr)}, {"sentence", a.sentence}};
}

Json KeyframePinnedJson(const KeyframePinned& k) { return {{"keyframe", k.keyframe_id}, {"pinned", k.pinned}}; }

Json KeyframeRelevanceJson(const KeyframeRelevance& k) { return {{"keyframe", k.keyframe_id}, {"relevance", k.relevance}}; }

Json ReanalyseJson(const ReanalyseResult& r) {
  Json segments = Json::array(), events = Json::array();
  for (const auto& s : r.segments) {
    Json item = SegmentJson(s.segment);
    item["known_instance"] = OrNull(s.known_instance);
    segments.push_back(item);
  }
  for (const auto& e : r.events) events.push_back(EventJson(e));
  return {{"keyframe", r.keyframe_id}, {"background_scene", r.background_scene_id}, {"segments", segments}, {"events", events}};
}

Json KeyframeAnalysisJson(const KeyframeAnalysis& a) {
  Json events = Json::array();
  for (const auto& e : a.events) events.push_back(EventJson(e));
  Json out = {{"events", events}, {"segments", a.segments}};
  if (a.action_layer) out["action_layer"] = *a.action_layer;
  return out;
}

Json KeyframeAnalysisStatusJson(const KeyframeAnalysisStatus& s) {
  Json out = s.result ? KeyframeAnalysisJson(*s.result) : Json::object();
  out["state"] = NameOf(kAnalysisStateNames, s.state);
  out["keyframe_id"] = s.keyframe_id;
  if (s.attempts > 0) out["attempts"] = s.attempts;
  if (s.last_error) out["last_error"] = *s.last_error;
  return out;
}

Json AnalysisQueueJson(const AnalysisQueueView& v) {
  Json failures = Json::array();
  for (const storage::QueuedAnalysis& q : v.failures) {
    failures.push_back({{"keyframe_id", q.keyframe_id}, {"scene_id", q.scene_id}, {"attempts", q.attempts},
                        {"last_error", q.last_error.value_or("")}, {"given_up", q.failed},
                        {"enqueued_ns", q.enqueued_ns}});
  }
  return {{"depth", v.pending},
          {"running", v.running},
          {"retrying", v.retrying},
          {"failed", v.failed},
          {"oldest_pending_age_s", v.oldest_pending_age_s ? Json(*v.oldest_pending_age_s) : Json(nullptr)},
          {"failures", failures}};
}

std::string AnalysisMetricsText(const AnalysisQueueView& all, const AnalysisCounters& c) {
  std::string out;
  const auto line = [&out](const char* name, const char* type, const char* help, double value) {
    out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + name + " " + std::to_string(value) + "\n";
  };
  line("anchordb_analysis_queue_depth", "gauge", "keyframe analyses queued or running", static_cast<double>(all.pending));
  line("anchordb_analysis_queue_oldest_age_seconds", "gauge", "age of the oldest queued keyframe analysis",
       all.oldest_pending_age_s.value_or(0.0));
  line("anchordb_analysis_given_up", "gauge", "keyframe analyses given up (kept in the queue, marked failed)", static_cast<double>(all.failed));
  line("anchordb_analysis_enqueued_total", "counter", "keyframe analyses queued since start", static_cast<double>(c.enqueued));
  line("anchordb_analysis_done_total", "counter", "keyframe analyses written since start", static_cast<double>(c.done));
  line("anchordb_analysis_skipped_total", "counter", "analyses skipped: their keyframe was deleted", static_cast<double>(c.skipped));
  line("anchordb_analysis_failures_total", "counter", "failed keyframe analysis attempts since start", static_cast<double>(c.failed_attempts));
  line("anchordb_analysis_busy_seconds_total", "counter", "time spent analysing keyframes", c.busy_s);
  line("anchordb_analysis_frames_refused_total", "counter",
       "frames and manual keyframes refused (503) because their map's analyses were analysis_max_pending behind",
       static_cast<double>(c.frames_refused));
  line("anchordb_analysis_caught_up_total", "counter", "analyses run at the requests' priority (a map analysis_catch_up_at behind)",
       static_cast<double>(c.caught_up));
  line("anchordb_analysis_raised_total", "counter", "running analyses raised to the requests' priority when their map fell behind",
       static_cast<double>(c.raised));
  line("anchordb_analysis_computed_in_write_total", "counter",
       "analyses computed inside their write transaction (other writers of the file wait meanwhile)", static_cast<double>(c.computed_in_write));
  return out;
}

}  // namespace anchordb::api
