#pragma once
// A grid layer's metadata as the API shows it (merged key by key into a layer's description by api/grid_json.cc):
//  occupancy:   geometry, map_server{image, resolution, origin, negate, occupied_thresh, free_thresh, mode,
//               mode_given}, ignored_yaml_keys
//  probability: geometry, base, log_odds{hit, miss, clamp_min, clamp_max}, observations
//  fused:       geometry, op, operands[{layer, threshold}]
//  label:       geometry, base, labels{"1": "kitchen"}
#include "schema/json_io.h"
#include "services/grid/grid_types.h"

namespace anchordb::api {

json::Json LayerMetaJson(const services::LayerMeta& meta);

}  // namespace anchordb::api
