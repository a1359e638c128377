#include "services/grid/grid_service.h"

#include "engine/grid/labels.h"
#include "engine/grid/log_odds.h"
#include "engine/grid/map_server.h"
#include "engine/grid/raster.h"
#include "schema/error.h"
#include "services/grid/grid_service_internal.h"

namespace anchordb::services {

using grid_detail::KindOps;
using grid_detail::MapLayers;

namespace {

MapInfo InfoOf(const storage::MapRecord& m) { return {m.id, m.name, m.created_ns}; }

storage::LayerRecord NewRecord(const std::string& map, const std::string& layer, std::int64_t now_ns) {
  storage::LayerRecord record;
  record.map_id = map;
  record.name = layer;
  record.created_ns = record.updated_ns = now_ns;
  return record;
}

// Stores the changed meta and data of `record` as its next version (kConflict if another writer was first).
void StoreNextVersion(storage::Connection& c, storage::LayerRecord& record, std::int64_t now_ns) {
  const std::int64_t expected = record.version;
  record.version = expected + 1;
  record.updated_ns = now_ns;
  storage::UpdateLayer(c, record, expected);
}

}  // namespace

GridService::GridService(storage::Store& store, ServiceLimits limits, GridDefaults defaults, const Clock& clock)
    : store_(store), limits_(limits), defaults_(defaults), clock_(clock) {}

// ---------------------------------------------------------------- maps

MapInfo GridService::CreateMap(const CreateMapRequest& request) {
  const storage::MapRecord m{request.id, request.name, clock_.NowNs()};
  store_.Write([&](storage::Connection& c) { storage::InsertMap(c, m); });
  return InfoOf(m);
}

MapPage GridService::ListMaps(const ListMapsRequest& request) {
  return store_.Read([&](storage::Connection& c) {
    const int limit = request.limit;
    const auto maps = storage::ListMaps(c, request.after_id, limit + 1);
    MapPage page;
    for (int i = 0; i < static_cast<int>(maps.size()) && i < limit; ++i) page.maps.push_back(InfoOf(maps[i]));
    if (static_cast<int>(maps.size()) > limit) page.next_cursor = maps[limit - 1].id;
    return page;
  });
}

MapDetails GridService::GetMap(const std::string& map) {
  return store_.Read([&](storage::Connection& c) {
    auto m = storage::FindMap(c, map);
    if (!m) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    MapDetails details{InfoOf(*m), {}, storage::ListAgents(c, map, std::nullopt).size()};
    for (const auto& l : storage::ListLayers(c, map)) details.layers.push_back({l.name, l.kind});
    return details;
  });
}

void GridService::DeleteMap(const std::string& map) {
  store_.Write([&](storage::Connection& c) {
    if (!storage::DeleteMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
  });
}

// ---------------------------------------------------------------- layers

LayerInfo GridService::ImportOccupancyLayer(const OccupancyImport& request) {
  // Decode and check everything before touching the database.
  engine::ParsedYaml parsed = engine::ParseMapServerYaml(request.yaml_text);
  engine::GreyImage image = engine::DecodeMapImage(request.image_bytes, limits_.max_map_pixels);
  const GridGeometry geometry = engine::GeometryOf(image, parsed.meta);
  storage::LayerRecord record = NewRecord(request.map, request.layer, clock_.NowNs());
  storage::EncodeLayer(storage::OccupancyLayer{{geometry, parsed.meta, parsed.ignored_keys}, std::move(image.pixels)},
                       record);
  return store_.Write([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    storage::InsertLayer(c, record, {});
    return grid_detail::DescribeLayer(layers.Require(request.layer, false));
  });
}

LayerInfo GridService::CreateLayer(const CreateLayerRequest& request) {
  const grid_detail::LayerKindOps& kind = KindOps(grid_detail::KindOf(request.spec));
  if (!kind.create) throw Error(ErrorCode::kInternal, "this layer kind is not created from a spec");
  storage::LayerRecord record = NewRecord(request.map, request.layer, clock_.NowNs());
  return store_.Write([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    const std::vector<std::string> depends_on = kind.create(layers, request.spec, record);
    storage::InsertLayer(c, record, depends_on);
    return grid_detail::DescribeLayer(layers.Require(request.layer, false));
  });
}

std::vector<LayerInfo> GridService::ListLayers(const std::string& map) {
  return store_.Read([&](storage::Connection& c) {
    grid_detail::RequireMap(c, map);
    std::vector<LayerInfo> out;
    for (const auto& l : storage::ListLayers(c, map)) out.push_back(grid_detail::DescribeLayer(l));
    return out;
  });
}

LayerInfo GridService::GetLayer(const std::string& map, const std::string& layer, bool with_statistics) {
  if (!with_statistics) {  // the common read in one statement; a miss (which of map and layer) and a layer with lists below
    const auto row = store_.ReadOneStatement([&](storage::Connection& c) { return storage::FindLayerRow(c, map, layer); });
    if (row && row->complete) return grid_detail::DescribeLayer(row->record);
  }
  return store_.Read([&](storage::Connection& c) {
    const MapLayers layers(c, map, /*check_map=*/false);
    const storage::LayerRecord record = layers.Require(layer, with_statistics);
    LayerInfo info = grid_detail::DescribeLayer(record);
    if (with_statistics) info.statistics = KindOps(record.kind).statistics(layers, record, defaults_.occupancy);
    return info;
  });
}

ExportedLayer GridService::ExportLayer(const std::string& map, const std::string& layer, LayerFormat format) {
  return store_.Read([&](storage::Connection& c) {
    const MapLayers layers(c, map, /*check_map=*/false);
    const storage::LayerRecord record = layers.Require(layer);
    const GridGeometry g = storage::DecodeGeometry(record);
    std::optional<ExportedLayer> own = KindOps(record.kind).export_own(record, format);
    ExportedLayer out = own ? std::move(*own) : grid_detail::ExportProbability(layers.Probability(record), layer, format);
    out.grid_width_cells = g.width_cells;
    out.grid_height_cells = g.height_cells;
    out.layer_version = record.version;
    return out;
  });
}

void GridService::DeleteLayer(const std::string& map, const std::string& layer) {
  store_.Write([&](storage::Connection& c) {
    grid_detail::RequireMap(c, map);
    const auto dependents = storage::LayerDependents(c, map, layer);
    if (!dependents.empty()) {
      std::string names;
      for (const auto& d : dependents) names += (names.empty() ? "" : ", ") + d;
      throw Error(ErrorCode::kConflict, "layer '" + layer + "' is used by " + names + "; delete those first", "layer");
    }
    if (!storage::DeleteLayer(c, map, layer)) {
      throw Error(ErrorCode::kNotFound, "layer '" + layer + "' does not exist in map '" + map + "'", "layer");
    }
  });
}

ObservationResult GridService::Observe(const ObserveRequest& request) {
  return store_.Write([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    storage::LayerRecord record = layers.Require(request.layer);
    if (record.kind != LayerKind::kProbability) {
      throw Error(ErrorCode::kUnprocessable, "observations update probability layers only; '" + request.layer + "' is " +
                                                 LayerKindName(record.kind), "layer");
    }
    storage::ProbabilityLayer layer = storage::DecodeProbabilityLayer(record);
    const grid_detail::OccupancyView base = grid_detail::DecodeOccupancyView(layers.Require(layer.meta.base));
    engine::LogOddsGrid grid = grid_detail::GridOf(layer.meta.geometry, std::move(layer.log_odds));
    if (!engine::SensorInsideGrid(grid.geometry, request.observation)) {
      throw Error(ErrorCode::kUnprocessable, "the sensor position lies outside the layer's grid", "pose.position");
    }
    const engine::ObservationCounts counts = engine::ApplyObservation(
        base.grid, defaults_.occupancy, engine::LogOddsModel(layer.meta.log_odds), request.observation, grid);
    layer.log_odds = std::move(grid.cells);
    ++layer.meta.observations;
    storage::EncodeLayer(layer, record);
    StoreNextVersion(c, record, clock_.NowNs());
    return ObservationResult{request.layer, record.version, counts};
  });
}

PaintLabelResult GridService::PaintLabel(const PaintLabelRequest& request) {
  return store_.Write([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    storage::LayerRecord record = layers.Require(request.layer);
    if (record.kind != LayerKind::kLabel) {
      throw Error(ErrorCode::kUnprocessable, "'" + request.layer + "' is not a label layer", "layer");
    }
    storage::LabelLayer layer = storage::DecodeLabelLayer(record);
    const engine::LabelIdChoice choice = engine::ChooseLabelId(layer.meta.labels, request.label);
    if (choice.is_new) layer.meta.labels[choice.id] = request.label;
    engine::LabelGrid grid = grid_detail::GridOf(layer.meta.geometry, std::move(layer.label_ids));
    engine::MaskGrid mask(grid.geometry, 0);
    const std::size_t cells = engine::RasterisePolygons(request.polygons_map, mask);
    engine::PaintMask(mask, static_cast<std::uint16_t>(choice.id), grid);
    layer.label_ids = std::move(grid.cells);
    storage::EncodeLayer(layer, record);
    StoreNextVersion(c, record, clock_.NowNs());
    return PaintLabelResult{request.layer, record.version, request.label, choice.id, cells};
  });
}

LayerRegions GridService::Regions(const RegionsRequest& request) {
  return store_.Read([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    const storage::LayerRecord record = layers.Require(request.layer);
    return LayerRegions{request.layer, record.version, request.threshold,
                        engine::ExtractRegions(layers.Probability(record), request.threshold, request.min_area_m2)};
  });
}

}  // namespace anchordb::services
