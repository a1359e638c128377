// Occupancy layers computed by another capability (the octomap's height bands): stored as map_server trinary
// images, so they export exactly like imported ones.
#include <algorithm>

#include "schema/error.h"
#include "services/grid/grid_service.h"
#include "services/grid/layer_kinds.h"
#include "storage/layer_codec.h"

namespace anchordb::services {

GridGeometry GridService::OccupancyGeometry(const std::string& map, const std::string& layer) {
  return store_.Read([&](storage::Connection& c) {
    const grid_detail::MapLayers layers(c, map);
    const storage::LayerRecord record = layers.Require(layer, false);
    if (record.kind != LayerKind::kOccupancy) {
      throw Error(ErrorCode::kUnprocessable, "layer '" + layer + "' is not an occupancy layer", "like");
    }
    return storage::DecodeGeometry(record);
  });
}

std::optional<std::string> GridService::FirstOccupancyLayer(const std::string& map,
                                                            const std::vector<std::string>& except) {
  for (const LayerInfo& l : ListLayers(map)) {
    if (l.kind == LayerKind::kOccupancy && std::find(except.begin(), except.end(), l.name) == except.end()) {
      return l.name;
    }
  }
  return std::nullopt;
}

std::vector<LayerInfo> GridService::PutOccupancyCells(
    const std::string& map, const GridGeometry& geometry,
    const std::vector<std::pair<std::string, std::vector<std::int8_t>>>& layers) {
  if (geometry.CellCount() > limits_.max_map_pixels) {
    throw Error(ErrorCode::kPayloadTooLarge, "the projected grid has " + std::to_string(geometry.CellCount()) +
                " cells, over max_map_pixels", "bands");
  }
  const std::int64_t now = clock_.NowNs();
  return store_.Write([&](storage::Connection& c) {
    const grid_detail::MapLayers existing(c, map);
    std::vector<LayerInfo> out;
    for (const auto& [name, cells] : layers) {
      if (cells.size() != geometry.CellCount()) throw Error(ErrorCode::kInternal, "cells do not match the grid");
      storage::OccupancyLayer layer;
      layer.meta.geometry = geometry;
      layer.meta.map_server.image = name + ".pgm";
      layer.meta.map_server.resolution_m = geometry.resolution_m;
      layer.meta.map_server.origin[0] = geometry.origin_x_m;
      layer.meta.map_server.origin[1] = geometry.origin_y_m;
      layer.meta.map_server.origin[2] = geometry.origin_yaw_rad;
      layer.image_pixels.resize(cells.size());
      for (int iy = 0; iy < geometry.height_cells; ++iy) {
        const int row = geometry.height_cells - 1 - iy;  // image row 0 is the top of the map
        for (int ix = 0; ix < geometry.width_cells; ++ix) {
          const std::int8_t v = cells[static_cast<std::size_t>(iy) * geometry.width_cells + ix];
          layer.image_pixels[static_cast<std::size_t>(row) * geometry.width_cells + ix] =
              v == 100 ? 0 : v == 0 ? 254 : 205;
        }
      }
      const std::optional<storage::LayerRecord> old = storage::FindLayer(c, map, name, false);
      storage::LayerRecord record;
      record.map_id = map;
      record.name = name;
      record.created_ns = old ? old->created_ns : now;
      record.updated_ns = now;
      storage::EncodeLayer(layer, record);
      if (!old) {
        storage::InsertLayer(c, record, {});
      } else {
        if (old->kind != LayerKind::kOccupancy) {
          throw Error(ErrorCode::kConflict, "layer '" + name + "' exists and is not an occupancy layer", "layer");
        }
        if (!(storage::DecodeGeometry(*old) == geometry) && !storage::LayerDependents(c, map, name).empty()) {
          throw Error(ErrorCode::kConflict, "layer '" + name + "' has dependent layers and a different grid", "layer");
        }
        record.version = old->version + 1;
        storage::UpdateLayer(c, record, old->version);
      }
      out.push_back(grid_detail::DescribeLayer(existing.Require(name, false)));
    }
    return out;
  });
}

}  // namespace anchordb::services
