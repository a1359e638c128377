#include "api/object_classification_json.h"

#include "schema/error.h"

namespace anchordb::api {

services::ClassifyInstanceRequest ParseClassifyInstanceRequest(const std::string& map, std::int64_t instance,
                                                               const Json& body) {
  json::RejectUnknownKeys(body, {"classifier"});
  services::ClassifyInstanceRequest r;
  r.map = map;
  r.instance = instance;
  r.classifier = json::RequireId(body, "classifier");
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
          {"segment", r.segment},
          {"keyframe", r.keyframe ? Json(*r.keyframe) : Json(nullptr)},
          {"points", r.points},
          {"features", features}};
}

}  // namespace anchordb::api
