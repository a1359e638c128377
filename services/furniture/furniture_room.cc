// The room a furniture graph stands in: the map's occupancy layer, read for the orientation prior (issue 17). The
// layer is decoded with the grid capability's occupancy reader, so both read map_server values the same way.
#include "services/furniture/furniture_service_internal.h"
#include "services/grid/layer_kinds.h"

namespace anchordb::services::furniture_detail {

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
