#pragma once
// The metadata documents of storage/layer_codec.h as JSON objects: what a layer's meta column holds, and what the
// API shows of a layer besides its record fields (api/grid_json.cc merges them into a layer's description).
#include "schema/json_io.h"
#include "storage/layer_codec.h"

namespace anchordb::storage {

json::Json MetaToJson(const OccupancyLayerMeta& meta);
json::Json MetaToJson(const ProbabilityLayerMeta& meta);
json::Json MetaToJson(const FusedLayerMeta& meta);
json::Json MetaToJson(const LabelLayerMeta& meta);

}  // namespace anchordb::storage
