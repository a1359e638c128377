#pragma once
// The metadata of each grid layer kind, as the layers table stores it in typed columns and child tables
// (migrations/*/0019): geometry for every kind, the map_server YAML and its ignored keys for occupancy layers, the
// base layer and log-odds update for probability layers, the operator and operands for fused layers, the base layer
// and label names for label layers. storage/layer_codec.h pairs it with the cells.
#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "schema/types.h"

namespace anchordb::storage {

struct OccupancyLayerMeta {
  GridGeometry geometry;
  MapServerMeta map_server;                    // the YAML values as imported
  std::vector<std::string> ignored_yaml_keys;  // YAML keys map_server does not know
};

struct ProbabilityLayerMeta {
  GridGeometry geometry;
  std::string base;  // the occupancy layer observations are ray-cast on
  LogOddsParams log_odds;
  std::int64_t observations = 0;  // observation updates applied so far
};

struct FusedLayerMeta {
  GridGeometry geometry;
  FuseOp op = FuseOp::kAnd;
  std::vector<FuseOperand> operands;  // layers of the same map, in order
};

struct LabelLayerMeta {
  GridGeometry geometry;
  std::string base;                   // the occupancy layer the labels were drawn over
  std::map<int, std::string> labels;  // label id (1..65535) -> name
};

// One alternative per LayerKind, in the order of its values.
using StoredLayerMeta = std::variant<OccupancyLayerMeta, ProbabilityLayerMeta, FusedLayerMeta, LabelLayerMeta>;

}  // namespace anchordb::storage
