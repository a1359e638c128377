#pragma once
// JSON of object classification (POST /v1/maps/{map}/instances/{instance}:classify; issue 15).
#include "api/http_api.h"
#include "services/classification/object_classification.h"

namespace anchordb::api {

// {"classifier": "<name>"}; anything else is refused.
services::ClassifyInstanceRequest ParseClassifyInstanceRequest(const std::string& map, std::int64_t instance,
                                                               const Json& body);
// {"instance", "classifier", "label", "distribution": {class: share}, "source": "classifier", "applied",
//  "labels": {...}, "label_source", "segment", "keyframe", "points", "features": {type: {"count", "bag"}}}
Json ToJson(const services::InstanceClassificationResult& r);

}  // namespace anchordb::api
