#include "services/grid/layer_kinds.h"

#include "engine/grid/layer_values.h"
#include "engine/grid/render.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::services::grid_detail {

const std::vector<const LayerKindOps*>& AllKinds() {
  static const std::vector<const LayerKindOps*> kinds = {&kOccupancyKind, &kProbabilityKind, &kFusedKind,
                                                         &kLabelKind};
  return kinds;
}

const LayerKindOps& KindOps(LayerKind kind) {
  for (const LayerKindOps* ops : AllKinds()) {
    if (ops->kind == kind) return *ops;
  }
  throw Error(ErrorCode::kInternal,
              "layer kind " + std::to_string(static_cast<int>(kind)) + " has no entry in the kind table");
}

LayerKind KindOf(const LayerSpec& spec) {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::kKind; }, spec);
}

// ---------------------------------------------------------------- MapLayers


MapLayers::MapLayers(storage::Connection& c, const std::string& map, bool check_map) : c_(c), map_(map) {
  if (check_map) RequireMap(c, map);
}

storage::LayerRecord MapLayers::Require(const std::string& layer, bool with_data) const {
  auto record = storage::FindLayer(c_, map_, layer, with_data);
  if (!record) RequireMap(c_, map_);  // a layer row implies its map (foreign key): checked only on a miss
  if (!record) throw Error(ErrorCode::kNotFound, "layer '" + layer + "' does not exist in map '" + map_ + "'", "layer");
  return std::move(*record);
}

storage::LayerRecord MapLayers::RequireOccupancy(const std::string& base) const {
  storage::LayerRecord record = Require(base);
  if (record.kind != LayerKind::kOccupancy) {
    throw Error(ErrorCode::kUnprocessable, "base layer '" + base + "' is not an occupancy layer", "base");
  }
  return record;
}

engine::ProbabilityGrid MapLayers::Probability(const storage::LayerRecord& record, int depth) const {
  if (depth > 8) throw Error(ErrorCode::kUnprocessable, "fused layers nest deeper than 8 levels");
  return KindOps(record.kind).probability(*this, record, depth);
}

std::string MapLayers::OccupancyBase(const storage::LayerRecord& record) const {
  return KindOps(record.kind).occupancy_base(*this, record);
}

// ---------------------------------------------------------------- shared by the kinds

LayerInfo DescribeLayer(const storage::LayerRecord& record) {
  LayerInfo info;
  info.map = record.map_id;
  info.name = record.name;
  info.kind = record.kind;
  info.version = record.version;
  info.created_ns = record.created_ns;
  info.updated_ns = record.updated_ns;
  info.stored_bytes = record.data_bytes;
  info.meta = KindOps(record.kind).meta(record);
  return info;
}

ExportedLayer ExportProbability(const engine::ProbabilityGrid& probability, const std::string& layer,
                                LayerFormat format) {
  switch (format) {
    case LayerFormat::kPng: return {.format = BytesFormat::kPng, .body = engine::EncodePng(engine::ProbabilityToImage(probability))};
    case LayerFormat::kPgm:
      return {.format = BytesFormat::kPgm, .body = engine::EncodePgm(engine::ProbabilityToImage(probability))};
    case LayerFormat::kYaml:
      return {.format = BytesFormat::kMapServerYaml,
              .body = engine::EmitMapServerYaml(engine::ScaleModeMeta(probability.geometry, layer + ".pgm"))};
    case LayerFormat::kRaw: {
      const engine::MaskGrid mask = engine::TrueCells(probability);
      return {.format = BytesFormat::kRaw, .body = std::string(storage::AsBytes(mask.cells)),
              .element = RawElement::kU8MaskCellOrder};
    }
  }
  throw Error(ErrorCode::kInternal, "unknown layer format");
}

OccupancyView DecodeOccupancyView(const storage::LayerRecord& record) {
  storage::OccupancyLayer layer = storage::DecodeOccupancyLayer(record);
  OccupancyView view;
  view.image.width = layer.meta.geometry.width_cells;
  view.image.height = layer.meta.geometry.height_cells;
  view.image.pixels = std::move(layer.image_pixels);
  view.map_server = layer.meta.map_server;
  view.grid = engine::ToOccupancy(view.image, view.map_server);
  return view;
}

}  // namespace anchordb::services::grid_detail
