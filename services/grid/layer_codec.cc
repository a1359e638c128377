#include "services/grid/layer_codec.h"

#include "engine/grid/fusion.h"
#include "engine/grid/log_odds.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::services::detail {

using storage::BlobElement;

namespace {
// Metadata is read from the database: a missing or mistyped field is a corrupt row (kInternal naming it), like a
// corrupt blob, not a JSON library exception.
template <typename F>
auto FromStoredMeta(const char* what, F&& read) {
  try {
    return read();
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::kInternal, std::string("stored layer metadata is corrupt (") + what + "): " + e.what());
  }
}
}  // namespace

Json ParseMeta(const storage::LayerRecord& record) {
  Json j = Json::parse(record.meta_json, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    throw Error(ErrorCode::kInternal, "stored metadata of layer '" + record.name + "' is not valid JSON");
  }
  return j;
}

GridGeometry GeometryFromMeta(const Json& meta) {
  return FromStoredMeta("geometry", [&] {
    const Json& g = meta.at("geometry");
    GridGeometry geometry;
    geometry.width_cells = g.at("width_cells").get<int>();
    geometry.height_cells = g.at("height_cells").get<int>();
    geometry.resolution_m = g.at("resolution_m").get<double>();
    geometry.origin_x_m = g.at("origin").at(0).get<double>();
    geometry.origin_y_m = g.at("origin").at(1).get<double>();
    geometry.origin_yaw_rad = g.at("origin").at(2).get<double>();
    return geometry;
  });
}

Json MapServerMetaToJson(const MapServerMeta& m) {
  return {{"image", m.image},         {"resolution", m.resolution_m},
          {"origin", {m.origin[0], m.origin[1], m.origin[2]}},
          {"negate", m.negate},       {"occupied_thresh", m.occupied_thresh},
          {"free_thresh", m.free_thresh}, {"mode", MapModeName(m.mode)}, {"mode_given", m.mode_given}};
}

MapServerMeta MapServerMetaFromJson(const Json& j) {
  return FromStoredMeta("map_server", [&] {
    MapServerMeta m;
    m.image = j.at("image").get<std::string>();
    m.resolution_m = j.at("resolution").get<double>();
    for (std::size_t i = 0; i < 3; ++i) m.origin[i] = j.at("origin").at(i).get<double>();
    m.negate = j.at("negate").get<int>();
    m.occupied_thresh = j.at("occupied_thresh").get<double>();
    m.free_thresh = j.at("free_thresh").get<double>();
    const std::string mode = j.at("mode").get<std::string>();
    m.mode = mode == "scale" ? MapMode::kScale : mode == "raw" ? MapMode::kRaw : MapMode::kTrinary;
    m.mode_given = j.at("mode_given").get<bool>();
    return m;
  });
}

std::string EncodeImageBlob(const engine::GreyImage& image) {
  return storage::EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(image.height), static_cast<std::uint32_t>(image.width)},
                             storage::AsBytes(image.pixels));
}

std::string EncodeLogOddsBlob(const engine::LogOddsGrid& grid) {
  const auto& g = grid.geometry;
  // Level 1: observation updates rewrite this blob on every call; speed matters more than the last percent.
  return storage::EncodeBlob(BlobElement::kF32, {static_cast<std::uint32_t>(g.height_cells), static_cast<std::uint32_t>(g.width_cells)},
                             storage::AsBytes(grid.cells), 1);
}

std::string EncodeLabelBlob(const engine::LabelGrid& grid) {
  const auto& g = grid.geometry;
  return storage::EncodeBlob(BlobElement::kU16, {static_cast<std::uint32_t>(g.height_cells), static_cast<std::uint32_t>(g.width_cells)},
                             storage::AsBytes(grid.cells));
}

namespace {
template <typename T>
std::vector<T> DecodeCells(const storage::LayerRecord& record, BlobElement element, const GridGeometry& g) {
  const storage::DecodedBlob blob = storage::DecodeBlob(record.data);
  if (blob.element != element || blob.shape.size() != 2 || static_cast<int>(blob.shape[0]) != g.height_cells ||
      static_cast<int>(blob.shape[1]) != g.width_cells) {
    throw Error(ErrorCode::kInternal, "stored data of layer '" + record.name + "' does not match its metadata");
  }
  std::vector<T> cells(g.CellCount());
  std::memcpy(cells.data(), blob.bytes.data(), blob.bytes.size());
  return cells;
}
}  // namespace

OccupancyLayer DecodeOccupancy(const storage::LayerRecord& record) {
  const Json meta = ParseMeta(record);
  OccupancyLayer out;
  out.meta = MapServerMetaFromJson(FromStoredMeta("map_server", [&]() -> const Json& { return meta.at("map_server"); }));
  const GridGeometry g = GeometryFromMeta(meta);
  out.image.width = g.width_cells;
  out.image.height = g.height_cells;
  out.image.pixels = DecodeCells<std::uint8_t>(record, BlobElement::kU8, g);
  out.grid = engine::ToOccupancy(out.image, out.meta);
  return out;
}

engine::LogOddsGrid DecodeLogOdds(const storage::LayerRecord& record) {
  engine::LogOddsGrid grid;
  grid.geometry = GeometryFromMeta(ParseMeta(record));
  grid.cells = DecodeCells<float>(record, BlobElement::kF32, grid.geometry);
  return grid;
}

engine::LabelGrid DecodeLabels(const storage::LayerRecord& record) {
  engine::LabelGrid grid;
  grid.geometry = GeometryFromMeta(ParseMeta(record));
  grid.cells = DecodeCells<std::uint16_t>(record, BlobElement::kU16, grid.geometry);
  return grid;
}

void RequireMap(storage::Connection& c, const std::string& map) {
  if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
}

storage::LayerRecord RequireLayer(storage::Connection& c, const std::string& map, const std::string& layer) {
  RequireMap(c, map);
  auto record = storage::FindLayer(c, map, layer, true);
  if (!record) throw Error(ErrorCode::kNotFound, "layer '" + layer + "' does not exist in map '" + map + "'", "layer");
  return std::move(*record);
}

engine::ProbabilityGrid EvaluateProbability(storage::Connection& c, const storage::LayerRecord& record, int depth) {
  if (depth > 8) throw Error(ErrorCode::kUnprocessable, "fused layers nest deeper than 8 levels");
  switch (record.kind) {
    case LayerKind::kOccupancy: {
      const OccupancyLayer occ = DecodeOccupancy(record);
      engine::ProbabilityGrid p(occ.grid.geometry, 0.5f);
      for (std::size_t i = 0; i < p.cells.size(); ++i) {
        const int v = occ.grid.cells[i];
        p.cells[i] = v < 0 ? 0.5f : std::min(100, v) / 100.0f;
      }
      return p;
    }
    case LayerKind::kProbability: return engine::ToProbability(DecodeLogOdds(record));
    case LayerKind::kLabel: {
      const engine::LabelGrid labels = DecodeLabels(record);
      engine::ProbabilityGrid p(labels.geometry, 0.0f);
      for (std::size_t i = 0; i < p.cells.size(); ++i) p.cells[i] = labels.cells[i] ? 1.0f : 0.0f;
      return p;
    }
    case LayerKind::kFused: {
      const Json meta = ParseMeta(record);
      std::vector<engine::MaskGrid> operands;
      for (const Json& op : meta.at("operands")) {
        const storage::LayerRecord operand = RequireLayer(c, record.map_id, op.at("layer").get<std::string>());
        operands.push_back(engine::Threshold(EvaluateProbability(c, operand, depth + 1), op.at("threshold").get<double>()));
      }
      const std::string name = meta.at("op").get<std::string>();
      const FuseOp fuse_op = name == "or" ? FuseOp::kOr : name == "and_not" ? FuseOp::kAndNot
                             : name == "xor" ? FuseOp::kXor : FuseOp::kAnd;
      const engine::MaskGrid mask = engine::Fuse(fuse_op, operands);
      engine::ProbabilityGrid p(mask.geometry, 0.0f);
      for (std::size_t i = 0; i < p.cells.size(); ++i) p.cells[i] = mask.cells[i];
      return p;
    }
  }
  throw Error(ErrorCode::kInternal, "unknown layer kind");
}

}  // namespace anchordb::services::detail
