#pragma once
// Internal to api/grid_service.cc and api/grid_attention.cc: the write guard of the service and the helpers both
// files use.
#include <string>

#include "services/grid/grid_service.h"
#include "services/grid/layer_codec.h"
#include "engine/grid/regions.h"
#include "schema/error.h"

namespace anchordb::services {

namespace grid_detail {

inline Json RegionJson(const engine::Region& r) {
  return {{"id", r.id},
          {"area_m2", r.area_m2},
          {"cells", r.cell_count},
          {"centroid", {r.centroid_m.x(), r.centroid_m.y()}},
          {"mean_probability", r.mean_probability},
          {"polygon", json::ToJson(r.polygon_m)}};
}

// The base layer of a probability/label layer must be an occupancy layer of the same map.
inline storage::LayerRecord RequireOccupancyBase(storage::Connection& c, const std::string& map, const std::string& base) {
  storage::LayerRecord record = detail::RequireLayer(c, map, base);
  if (record.kind != LayerKind::kOccupancy) {
    throw Error(ErrorCode::kUnprocessable, "base layer '" + base + "' is not an occupancy layer", "base");
  }
  return record;
}

}  // namespace grid_detail


}  // namespace anchordb::services
