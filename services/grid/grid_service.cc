#include "services/grid/grid_service.h"

#include <chrono>
#include <cmath>

#include "services/grid/grid_service_internal.h"
#include "engine/grid/fusion.h"
#include "engine/grid/log_odds.h"
#include "engine/grid/raster.h"
#include "engine/grid/render.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::services {

using namespace detail;       // NOLINT: the codec helpers are this file's vocabulary
using namespace grid_detail;  // NOLINT

namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Json MapJson(const storage::MapRecord& m) { return {{"id", m.id}, {"name", m.name}, {"created_ns", m.created_ns}}; }

Json LayerSummary(const storage::LayerRecord& l) {
  Json meta = ParseMeta(l);
  Json out = {{"map", l.map_id},         {"name", l.name},       {"kind", LayerKindName(l.kind)},
              {"version", l.version},     {"created_ns", l.created_ns}, {"updated_ns", l.updated_ns},
              {"stored_bytes", l.data_bytes}};
  for (auto& [key, value] : meta.items()) out[key] = value;
  return out;
}

}  // namespace

GridService::GridService(storage::Store& store, ServiceLimits limits, GridDefaults defaults)
    : store_(store), limits_(limits), defaults_(defaults) {}

// ---------------------------------------------------------------- maps

Json GridService::CreateMap(const std::string& id, const std::string& name) {
  storage::MapRecord m{id, name, NowNs()};
  store_.Write([&](storage::Connection& c) { storage::InsertMap(c, m); });
  return MapJson(m);
}

Json GridService::ListMaps(const std::string& after_id, int limit) {
  return store_.Read([&](storage::Connection& c) {
    const auto maps = storage::ListMaps(c, after_id, limit + 1);
    Json out = {{"maps", Json::array()}, {"next_cursor", nullptr}};
    for (int i = 0; i < static_cast<int>(maps.size()) && i < limit; ++i) out["maps"].push_back(MapJson(maps[i]));
    if (static_cast<int>(maps.size()) > limit) out["next_cursor"] = maps[limit - 1].id;
    return out;
  });
}

Json GridService::GetMap(const std::string& id) {
  return store_.Read([&](storage::Connection& c) {
    auto m = storage::FindMap(c, id);
    if (!m) throw Error(ErrorCode::kNotFound, "map '" + id + "' does not exist", "map");
    Json out = MapJson(*m);
    out["layers"] = Json::array();
    for (const auto& l : storage::ListLayers(c, id)) out["layers"].push_back({{"name", l.name}, {"kind", LayerKindName(l.kind)}});
    out["agents"] = storage::ListAgents(c, id, std::nullopt).size();
    return out;
  });
}

void GridService::DeleteMap(const std::string& id) {
  store_.Write([&](storage::Connection& c) {
    if (!storage::DeleteMap(c, id)) throw Error(ErrorCode::kNotFound, "map '" + id + "' does not exist", "map");
  });
}

// ---------------------------------------------------------------- layers

Json GridService::ImportOccupancyLayer(const std::string& map, const std::string& layer, std::string_view yaml_text,
                                       std::string_view image_bytes) {
  // Decode and check everything before touching the database.
  engine::ParsedYaml parsed = engine::ParseMapServerYaml(yaml_text);
  const engine::GreyImage image = engine::DecodeMapImage(image_bytes, limits_.max_map_pixels);
  const GridGeometry geometry = engine::GeometryOf(image, parsed.meta);
  storage::LayerRecord record;
  record.map_id = map;
  record.name = layer;
  record.kind = LayerKind::kOccupancy;
  record.meta_json = Json{{"geometry", json::ToJson(geometry)},
                          {"map_server", MapServerMetaToJson(parsed.meta)},
                          {"ignored_yaml_keys", parsed.ignored_keys}}.dump();
  record.data = EncodeImageBlob(image);
  record.created_ns = record.updated_ns = NowNs();
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::InsertLayer(c, record, {});
    return LayerSummary(*storage::FindLayer(c, map, layer, false));
  });
}

Json GridService::CreateLayer(const std::string& map, const std::string& layer, const Json& body) {
  const std::string kind = json::RequireString(body, "kind", 32);
  storage::LayerRecord record;
  record.map_id = map;
  record.name = layer;
  record.created_ns = record.updated_ns = NowNs();
  if (kind == "probability" || kind == "label") {
    if (kind == "probability") json::RejectUnknownKeys(body, {"kind", "base", "log_odds"});
    else json::RejectUnknownKeys(body, {"kind", "base", "labels"});
    const std::string base = json::RequireId(body, "base");
    LogOddsParams params;
    Json labels = Json::object();
    if (kind == "probability") {
      if (body.contains("log_odds")) {
        if (!body["log_odds"].is_object()) throw Error(ErrorCode::kInvalidArgument, "log_odds must be an object", "log_odds");
        json::RejectUnknownKeys(body["log_odds"], {"hit", "miss", "clamp_min", "clamp_max"}, "log_odds");
        params = json::AsLogOddsParams(body["log_odds"], "log_odds");
      }
    } else if (body.contains("labels")) {
      if (!body["labels"].is_object()) throw Error(ErrorCode::kInvalidArgument, "labels must be an object {\"1\":\"kitchen\"}", "labels");
      for (const auto& [id, name] : body["labels"].items()) {
        const int n = std::atoi(id.c_str());
        if (n < 1 || n > 65535 || std::to_string(n) != id || !name.is_string()) {
          throw Error(ErrorCode::kInvalidArgument, "labels: keys are ids 1-65535, values names", "labels." + id);
        }
        labels[id] = name;
      }
    }
    return store_.Write([&](storage::Connection& c) {
      const storage::LayerRecord base_record = RequireOccupancyBase(c, map, base);
      const GridGeometry geometry = GeometryFromMeta(ParseMeta(base_record));
      Json meta = {{"geometry", json::ToJson(geometry)}, {"base", base}};
      if (kind == "probability") {
        record.kind = LayerKind::kProbability;
        meta["log_odds"] = json::ToJson(params);
        meta["observations"] = 0;
        record.data = EncodeLogOddsBlob(engine::LogOddsGrid(geometry, 0.0f));
      } else {
        record.kind = LayerKind::kLabel;
        meta["labels"] = labels;
        record.data = EncodeLabelBlob(engine::LabelGrid(geometry, 0));
      }
      record.meta_json = meta.dump();
      storage::InsertLayer(c, record, {base});
      return LayerSummary(*storage::FindLayer(c, map, layer, false));
    });
  }
  if (kind == "fused") {
    json::RejectUnknownKeys(body, {"kind", "op", "operands"});
    const std::string op = json::RequireString(body, "op", 16);
    if (op != "and" && op != "or" && op != "and_not" && op != "xor") {
      throw Error(ErrorCode::kInvalidArgument, "op must be and, or, and_not or xor", "op");
    }
    const Json& operands = json::Require(body, "operands");
    if (!operands.is_array() || operands.size() < 2 || operands.size() > 16) {
      throw Error(ErrorCode::kInvalidArgument, "operands must be an array of 2-16 {\"layer\",\"threshold\"}", "operands");
    }
    Json stored = Json::array();
    std::vector<std::string> depends;
    for (std::size_t i = 0; i < operands.size(); ++i) {
      const std::string path = "operands[" + std::to_string(i) + "]";
      if (!operands[i].is_object()) throw Error(ErrorCode::kInvalidArgument, path + " must be an object", path);
      json::RejectUnknownKeys(operands[i], {"layer", "threshold"}, path);
      const std::string name = json::RequireId(operands[i], "layer", path);
      const double threshold = json::FiniteNumberOr(operands[i], "threshold", 0.5, path);
      if (threshold < 0.0 || threshold > 1.0) {
        throw Error(ErrorCode::kUnprocessable, path + ".threshold must be in [0, 1]", path + ".threshold");
      }
      if (name == layer) throw Error(ErrorCode::kUnprocessable, "a fused layer cannot use itself", path + ".layer");
      stored.push_back({{"layer", name}, {"threshold", threshold}});
      depends.push_back(name);
    }
    return store_.Write([&](storage::Connection& c) {
      std::optional<GridGeometry> geometry;
      for (std::size_t i = 0; i < depends.size(); ++i) {
        const auto operand = RequireLayer(c, map, depends[i]);
        const GridGeometry g = GeometryFromMeta(ParseMeta(operand));
        if (geometry && !(*geometry == g)) {
          throw Error(ErrorCode::kUnprocessable, "operands cover different grids", "operands[" + std::to_string(i) + "]");
        }
        geometry = g;
      }
      record.kind = LayerKind::kFused;
      record.meta_json = Json{{"geometry", json::ToJson(*geometry)}, {"op", op}, {"operands", stored}}.dump();
      storage::InsertLayer(c, record, depends);
      return LayerSummary(*storage::FindLayer(c, map, layer, false));
    });
  }
  throw Error(ErrorCode::kInvalidArgument, "kind must be probability, fused or label (occupancy layers are imported "
                                           "as multipart yaml + image)", "kind");
}

Json GridService::ListLayers(const std::string& map) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    Json out = {{"layers", Json::array()}};
    for (const auto& l : storage::ListLayers(c, map)) out["layers"].push_back(LayerSummary(l));
    return out;
  });
}

Json GridService::LayerInfo(const std::string& map, const std::string& layer, bool with_statistics) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto record = storage::FindLayer(c, map, layer, with_statistics);
    if (!record) throw Error(ErrorCode::kNotFound, "layer '" + layer + "' does not exist in map '" + map + "'", "layer");
    Json out = LayerSummary(*record);
    if (with_statistics) {
      Json stats;
      if (record->kind == LayerKind::kOccupancy) {
        const OccupancyLayer occ = DecodeOccupancy(*record);
        std::size_t occupied = 0, free = 0, unknown = 0;
        for (auto v : occ.grid.cells) {
          if (engine::IsOccupied(v, defaults_.occupancy)) ++occupied;
          else if (engine::IsFree(v, defaults_.occupancy)) ++free;
          else ++unknown;
        }
        stats = {{"occupied_cells", occupied}, {"free_cells", free}, {"unknown_cells", unknown}};
      } else if (record->kind == LayerKind::kLabel) {
        const engine::LabelGrid labels = DecodeLabels(*record);
        std::map<int, std::size_t> counts;
        for (auto v : labels.cells) if (v) ++counts[v];
        Json per = Json::object();
        for (auto [id, n] : counts) per[std::to_string(id)] = n;
        stats = {{"cells_per_label", per}};
      } else {
        const engine::ProbabilityGrid p = EvaluateProbability(c, *record);
        double sum = 0, lo = 1, hi = 0;
        std::size_t above = 0;
        for (float v : p.cells) sum += v, lo = std::min<double>(lo, v), hi = std::max<double>(hi, v), above += v > 0.5f;
        stats = {{"min_probability", lo}, {"max_probability", hi},
                 {"mean_probability", p.cells.empty() ? 0.0 : sum / p.cells.size()}, {"cells_above_0_5", above}};
      }
      out["statistics"] = stats;
    }
    return out;
  });
}

ExportedLayer GridService::ExportLayer(const std::string& map, const std::string& layer, const std::string& format) {
  return store_.Read([&](storage::Connection& c) {
    const storage::LayerRecord record = RequireLayer(c, map, layer);
    ExportedLayer out;
    const GridGeometry g = GeometryFromMeta(ParseMeta(record));
    out.headers = {{"X-Grid-Width", std::to_string(g.width_cells)}, {"X-Grid-Height", std::to_string(g.height_cells)},
                   {"X-Layer-Version", std::to_string(record.version)}};
    if (record.kind == LayerKind::kOccupancy) {
      const OccupancyLayer occ = DecodeOccupancy(record);
      if (format == "png") out = {"image/png", engine::EncodePng(occ.image), out.headers};
      else if (format == "pgm") out = {"image/x-portable-graymap", engine::EncodePgm(occ.image), out.headers};
      else if (format == "yaml") {
        MapServerMeta meta = occ.meta;
        meta.image = layer + ".pgm";
        out = {"application/yaml", engine::EmitMapServerYaml(meta), out.headers};
      } else if (format == "raw") {
        out.content_type = "application/octet-stream";
        out.body.assign(occ.image.pixels.begin(), occ.image.pixels.end());
        out.headers["X-Element"] = "u8-image-order";
      } else throw Error(ErrorCode::kInvalidArgument, "format must be json, png, pgm, yaml or raw", "format");
      return out;
    }
    if (record.kind == LayerKind::kLabel && format == "png") return ExportedLayer{"image/png", engine::RenderLabelsPng(DecodeLabels(record)), out.headers};
    if (format == "raw") {
      out.content_type = "application/octet-stream";
      if (record.kind == LayerKind::kProbability) {
        const auto grid = DecodeLogOdds(record);
        out.body.assign(storage::AsBytes(grid.cells));
        out.headers["X-Element"] = "f32-log-odds-cell-order";
      } else if (record.kind == LayerKind::kLabel) {
        const auto grid = DecodeLabels(record);
        out.body.assign(storage::AsBytes(grid.cells));
        out.headers["X-Element"] = "u16-label-cell-order";
      } else {
        const auto p = EvaluateProbability(c, record);
        out.body.resize(p.cells.size());
        for (std::size_t i = 0; i < p.cells.size(); ++i) out.body[i] = p.cells[i] > 0.5f ? 1 : 0;
        out.headers["X-Element"] = "u8-mask-cell-order";
      }
      return out;
    }
    const engine::GreyImage image = engine::ProbabilityToImage(EvaluateProbability(c, record));
    if (format == "png") return ExportedLayer{"image/png", engine::EncodePng(image), out.headers};
    if (format == "pgm") return ExportedLayer{"image/x-portable-graymap", engine::EncodePgm(image), out.headers};
    if (format == "yaml") {
      MapServerMeta meta;
      meta.image = layer + ".pgm";
      meta.resolution_m = g.resolution_m;
      meta.origin[0] = g.origin_x_m, meta.origin[1] = g.origin_y_m, meta.origin[2] = g.origin_yaw_rad;
      meta.mode = MapMode::kScale;
      meta.mode_given = true;
      return ExportedLayer{"application/yaml", engine::EmitMapServerYaml(meta), out.headers};
    }
    throw Error(ErrorCode::kInvalidArgument, "format must be json, png, pgm, yaml or raw", "format");
  });
}

void GridService::DeleteLayer(const std::string& map, const std::string& layer) {
  store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
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

Json GridService::Observe(const std::string& map, const std::string& layer, const engine::Observation& observation) {
  return store_.Write([&](storage::Connection& c) {
    storage::LayerRecord record = RequireLayer(c, map, layer);
    if (record.kind != LayerKind::kProbability) {
      throw Error(ErrorCode::kUnprocessable, "observations update probability layers only; '" + layer + "' is " +
                                                 LayerKindName(record.kind), "layer");
    }
    Json meta = ParseMeta(record);
    const storage::LayerRecord base = RequireLayer(c, map, meta.at("base").get<std::string>());
    const OccupancyLayer occupancy = DecodeOccupancy(base);
    engine::LogOddsGrid grid = DecodeLogOdds(record);
    const Eigen::Vector2d sensor_grid = grid.geometry.MapToGrid(observation.sensor_position_m);
    if (!grid.geometry.Contains(static_cast<int>(std::floor(sensor_grid.x())), static_cast<int>(std::floor(sensor_grid.y())))) {
      throw Error(ErrorCode::kUnprocessable, "the sensor position lies outside the layer's grid", "pose.position");
    }
    LogOddsParams params;
    params.hit_probability = meta["log_odds"]["hit"].get<double>();
    params.miss_probability = meta["log_odds"]["miss"].get<double>();
    params.clamp_min_probability = meta["log_odds"]["clamp_min"].get<double>();
    params.clamp_max_probability = meta["log_odds"]["clamp_max"].get<double>();
    const engine::ObservationCounts counts = engine::ApplyObservation(
        occupancy.grid, defaults_.occupancy, engine::LogOddsModel(params), observation, grid);
    const std::int64_t expected = record.version;
    meta["observations"] = meta.value("observations", 0) + 1;
    record.meta_json = meta.dump();
    record.data = EncodeLogOddsBlob(grid);
    record.version = expected + 1;
    record.updated_ns = NowNs();
    storage::UpdateLayer(c, record, expected);
    return Json{{"layer", layer}, {"version", record.version}, {"cells_raised", counts.raised},
                {"cells_lowered", counts.lowered}, {"cells_unchanged_blocked", counts.unchanged_blocked},
                {"stimulus_cells_outside_view", counts.stimulus_outside_view}};
  });
}

Json GridService::PaintLabel(const std::string& map, const std::string& layer, const std::string& label,
                             const std::vector<Polygon2>& polygons) {
  return store_.Write([&](storage::Connection& c) {
    storage::LayerRecord record = RequireLayer(c, map, layer);
    if (record.kind != LayerKind::kLabel) {
      throw Error(ErrorCode::kUnprocessable, "'" + layer + "' is not a label layer", "layer");
    }
    Json meta = ParseMeta(record);
    int id = 0, max_id = 0;
    for (const auto& [key, name] : meta["labels"].items()) {
      max_id = std::max(max_id, std::atoi(key.c_str()));
      if (name.get<std::string>() == label) id = std::atoi(key.c_str());
    }
    if (id == 0) {
      if (max_id >= 65535) throw Error(ErrorCode::kUnprocessable, "label layer holds 65535 labels already", "label");
      id = max_id + 1;
      meta["labels"][std::to_string(id)] = label;
    }
    engine::LabelGrid grid = DecodeLabels(record);
    engine::MaskGrid mask(grid.geometry, 0);
    const std::size_t cells = engine::RasterisePolygons(polygons, mask);
    for (std::size_t i = 0; i < mask.cells.size(); ++i) if (mask.cells[i]) grid.cells[i] = static_cast<std::uint16_t>(id);
    const std::int64_t expected = record.version;
    record.meta_json = meta.dump();
    record.data = EncodeLabelBlob(grid);
    record.version = expected + 1;
    record.updated_ns = NowNs();
    storage::UpdateLayer(c, record, expected);
    return Json{{"layer", layer}, {"version", record.version}, {"label", label}, {"label_id", id}, {"cells", cells}};
  });
}

Json GridService::Regions(const std::string& map, const std::string& layer, double threshold, double min_area_m2) {
  return store_.Read([&](storage::Connection& c) {
    const storage::LayerRecord record = RequireLayer(c, map, layer);
    const auto regions = engine::ExtractRegions(EvaluateProbability(c, record), threshold, min_area_m2);
    Json out = {{"layer", layer}, {"version", record.version}, {"threshold", threshold}, {"regions", Json::array()}};
    for (const auto& r : regions) out["regions"].push_back(RegionJson(r));
    return out;
  });
}

}  // namespace anchordb::services
