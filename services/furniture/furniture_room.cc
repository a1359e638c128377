// The room a furniture graph stands in: the map's occupancy layer, read for the orientation prior (issue 17). The
// layer is decoded with the grid capability's occupancy reader, so both read map_server values the same way.
#include "services/furniture/furniture_service_internal.h"
#include "services/grid/layer_kinds.h"

namespace anchordb::services::furniture_detail {

std::string DefaultOccupancyLayer(storage::Store& store, const std::string& map) {
  const auto layers = store.Read([&](storage::Connection& c) { return storage::ListLayers(c, map); });
  std::vector<std::string> occupancy;
  for (const storage::LayerRecord& l : layers) {
    if (l.kind != LayerKind::kOccupancy) continue;
    if (l.name == "occupancy") return l.name;
    occupancy.push_back(l.name);
  }
  return occupancy.size() == 1 ? occupancy.front() : std::string();
}

std::optional<engine::OccupancyGrid> OccupancyOf(storage::Store& store, const std::string& map, const std::string& layer) {
  if (layer.empty()) return std::nullopt;
  const auto record = store.Read([&](storage::Connection& c) { return storage::FindLayer(c, map, layer, true); });
  if (!record) throw Error(ErrorCode::kNotFound, "map '" + map + "' has no layer '" + layer + "'", "params.occupancy_layer");
  if (record->kind != LayerKind::kOccupancy) {
    throw Error(ErrorCode::kUnprocessable, "layer '" + layer + "' is not an occupancy layer", "params.occupancy_layer");
  }
  return grid_detail::DecodeOccupancyView(*record).grid;
}

}  // namespace anchordb::services::furniture_detail
