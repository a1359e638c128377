#include "api/object_classification_json.h"

#include "schema/error.h"

namespace anchordb::api {

services::ClassifyInstanceRequest ParseClassifyInstanceRequest(const std::string& map, std::int64_t instance,
                                                               const Json& body) {
  json::RejectUnknownKeys(body, {"classifier", "keypoint_spacing_m", "min_points"});
  services::ClassifyInstanceRequest r;
  r.map = map;
  r.instance = instance;
  r.classifier = json::RequireId(body, "classifier");
  if (body.contains("keypoint_spacing_m")) r.keypoint_spacing_m = json::AsFiniteNumber(body["keypoint_spacing_m"], "keypoint_spacing_m");
  const std::int64_t min_points = json::IntegerOr(body, "min_points", r.min_points);
  // The service checks the ranges; a value past int is out of range too.
  r.min_points = min_points > 1000000 || min_points < 0 ? -1 : static_cast<int>(min_points);
  return r;
}

Json ToJson(const services::InstanceClassificationResult& r) {
  Json distribution = Json::object();
  for (const auto& [label, share] : r.distribution) distribution[label] = share;
  Json features = Json::object();
  for (const auto& t : r.types) features[t.type] = {{"count", t.features}, {"bag", t.bag}};
  return {{"instance", r.instance},
          {"classifier", r.classifier},
          {"label", r.label},
          {"distribution", distribution},
          {"source", "classifier"},
          {"applied", r.applied},
          {"labels", Json(r.labels)},
          {"label_source", r.label_source},
          {"event", r.event ? Json(*r.event) : Json(nullptr)},
          {"segment", r.segment},
          {"keyframe", r.keyframe ? Json(*r.keyframe) : Json(nullptr)},
          {"points", r.points},
          {"features", features}};
}

}  // namespace anchordb::api
