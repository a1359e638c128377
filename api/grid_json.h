#pragma once
// JSON of the grid routes: request bodies -> typed GridService requests (strict: unknown keys, wrong types and
// out-of-range values are Error kInvalidArgument / kUnprocessable naming the field), typed results -> the JSON
// documents clients see.
#include <string>
#include <vector>

#include "schema/json_io.h"
#include "services/grid/grid_service.h"

namespace anchordb::api::grid_json {

using json::Json;

// ---- requests
services::CreateMapRequest ParseCreateMap(const Json& body);
// {"kind":"probability","base":..,"log_odds":{..}} | {"kind":"fused","op":..,"operands":[{layer,threshold}..]} |
// {"kind":"label","base":..,"labels":{"1":"kitchen"}}; `layer` is the layer being created (it may not fuse itself).
services::LayerSpec ParseLayerSpec(const Json& body, const std::string& layer);
// png | pgm | yaml | raw
services::LayerFormat ParseLayerFormat(const std::string& format);
engine::Observation ParseObservation(const Json& body, const services::ServiceLimits& limits);
services::PaintLabelRequest ParsePaintLabel(const Json& body, const services::ServiceLimits& limits);
services::PutAgentRequest ParsePutAgent(const Json& body);
services::ViewpointsRequest ParseViewpoints(const Json& body);

// ---- results
Json ToJson(const services::MapInfo& map);
Json ToJson(const services::MapPage& page);
Json ToJson(const services::MapDetails& details);
Json ToJson(const services::LayerInfo& layer);
Json ToJson(const std::vector<services::LayerInfo>& layers);  // {"layers":[..]}
Json ToJson(const services::ObservationResult& result);
Json ToJson(const services::PaintLabelResult& result);
Json ToJson(const services::LayerRegions& regions);
Json ToJson(const std::vector<Agent>& agents);  // {"agents":[..]}
Json ToJson(const services::AttentionResult& result);
Json ToJson(const services::ViewpointsResult& result);

}  // namespace anchordb::api::grid_json
