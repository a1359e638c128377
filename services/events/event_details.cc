// The details document of change events (see event_details.h).
#include "services/events/event_details.h"

#include "schema/json_io.h"
#include "storage/event_repository.h"

namespace anchordb::services {

using json::Json;

namespace {

Json Vec3Json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d Vec3Of(const Json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

}  // namespace

std::string EncodeEventDetails(const EventDetails& d) {
  Json j = Json::object();
  if (d.segment) {
    j["segment"] = {{"centroid_m", Vec3Json(d.segment->centroid_m)}, {"extent_m", Vec3Json(d.segment->extent_m)},
                    {"points", d.segment->points}};
  }
  if (d.move) {
    j["from_m"] = Vec3Json(d.move->from_m);
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
  return j.dump();
}

EventDetails DecodeEventDetails(const std::string& details_json) {
  const Json j = Json::parse(details_json);
  EventDetails d;
  if (j.contains("segment")) {
    const Json& s = j["segment"];
    d.segment = engine::SegmentSummary{Vec3Of(s.at("centroid_m")), Vec3Of(s.at("extent_m")), s.at("points").get<std::int64_t>()};
  }
  if (j.contains("from_m")) {
    d.move = MoveEvidence{Vec3Of(j["from_m"]), j.value("size_similarity", 0.0), std::nullopt};
    if (j.contains("removal_event") && !j["removal_event"].is_null()) d.move->removal_event = j["removal_event"].get<std::int64_t>();
  }
  if (j.contains("visibility")) {
    const Json& v = j["visibility"];
    d.visibility = engine::Visibility{v.at("outside").get<int>(), v.at("confirmed").get<int>(), v.at("seen_through").get<int>(),
                                      v.at("hidden").get<int>(), v.at("unmeasured").get<int>()};
  }
  if (j.contains("background_scene")) d.background_scene = j["background_scene"].get<std::int64_t>();
  if (j.contains("labels")) d.labels = j["labels"].get<engine::LabelWeights>();
  return d;
}

std::int64_t InsertLabelledEvent(storage::Connection& c, const std::string& map, std::int64_t instance,
                                 const std::string& label, const std::string& detection, std::int64_t stamp_ns,
                                 const std::string& explanation, const engine::LabelWeights& distribution) {
  storage::EventRecord e;
  e.map_id = map;
  e.type = "labelled";
  e.detection = detection;
  e.stamp_ns = stamp_ns;
  e.created_ns = stamp_ns;
  e.instance_id = instance;
  e.label = label;
  e.explanation = explanation;
  EventDetails details;
  details.labels = distribution;
  e.details_json = EncodeEventDetails(details);
  return storage::InsertEvent(c, e);
}

}  // namespace anchordb::services
