// A grid layer's metadata as JSON for the API.
#include "api/layer_meta_json.h"

#include <string>
#include <variant>

namespace anchordb::api {

using json::Json;

namespace {

Json MapServerJson(const MapServerMeta& m) {
  return {{"image", m.image},         {"resolution", m.resolution_m},
          {"origin", {m.origin[0], m.origin[1], m.origin[2]}},
          {"negate", m.negate},       {"occupied_thresh", m.occupied_thresh},
          {"free_thresh", m.free_thresh}, {"mode", MapModeName(m.mode)}, {"mode_given", m.mode_given}};
}

Json MetaJson(const storage::OccupancyLayerMeta& m) {
  return {{"geometry", json::ToJson(m.geometry)}, {"map_server", MapServerJson(m.map_server)},
          {"ignored_yaml_keys", m.ignored_yaml_keys}};
}

Json MetaJson(const storage::ProbabilityLayerMeta& m) {
  return {{"geometry", json::ToJson(m.geometry)}, {"base", m.base}, {"log_odds", json::ToJson(m.log_odds)},
          {"observations", m.observations}};
}

Json MetaJson(const storage::FusedLayerMeta& m) {
  Json operands = Json::array();
  for (const FuseOperand& o : m.operands) operands.push_back({{"layer", o.layer}, {"threshold", o.threshold}});
  return {{"geometry", json::ToJson(m.geometry)}, {"op", FuseOpName(m.op)}, {"operands", operands}};
}

Json MetaJson(const storage::LabelLayerMeta& m) {
  Json labels = Json::object();
  for (const auto& [id, name] : m.labels) labels[std::to_string(id)] = name;
  return {{"geometry", json::ToJson(m.geometry)}, {"base", m.base}, {"labels", labels}};
}

}  // namespace

Json LayerMetaJson(const services::LayerMeta& meta) {
  return std::visit([](const auto& m) { return MetaJson(m); }, meta);
}

}  // namespace anchordb::api
