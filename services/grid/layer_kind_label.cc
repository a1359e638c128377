// Label layers: a label id per cell over an occupancy layer, painted over polygons (GridService::PaintLabel).
#include "engine/grid/layer_values.h"
#include "engine/grid/render.h"
#include "services/grid/layer_kinds.h"
#include "storage/blob_codec.h"

namespace anchordb::services::grid_detail {
namespace {

std::vector<std::string> Create(const MapLayers& layers, const LayerSpec& spec, storage::LayerRecord& record) {
  const auto& s = std::get<LabelLayerSpec>(spec);
  const GridGeometry geometry = storage::DecodeGeometry(layers.RequireOccupancy(s.base));
  std::vector<std::uint16_t> label_ids(geometry.CellCount(), 0);  // no cell labelled
  storage::EncodeLayer(storage::LabelLayer{{geometry, s.base, s.labels}, std::move(label_ids)}, record);
  return {s.base};
}

LayerMeta Meta(const storage::LayerRecord& record) { return storage::DecodeLabelMeta(record); }

engine::LabelGrid Labels(const storage::LayerRecord& record) {
  storage::LabelLayer layer = storage::DecodeLabelLayer(record);
  return GridOf(layer.meta.geometry, std::move(layer.label_ids));
}

engine::ProbabilityGrid Probability(const MapLayers&, const storage::LayerRecord& record, int) {
  return engine::LabelsToProbability(Labels(record));
}

LayerStatistics Statistics(const MapLayers&, const storage::LayerRecord& record, const engine::OccupancyThresholds&) {
  return engine::CountLabels(Labels(record));
}

// png shows each label in its colour, raw the stored ids; pgm and YAML show where any label is.
std::optional<ExportedLayer> ExportOwn(const storage::LayerRecord& record, LayerFormat format) {
  if (format == LayerFormat::kPng) {
    return ExportedLayer{.format = BytesFormat::kPng, .body = engine::RenderLabelsPng(Labels(record))};
  }
  if (format != LayerFormat::kRaw) return std::nullopt;
  return ExportedLayer{.format = BytesFormat::kRaw, .body = std::string(storage::AsBytes(Labels(record).cells)),
                       .element = RawElement::kU16LabelCellOrder};
}

std::string OccupancyBase(const MapLayers&, const storage::LayerRecord& record) {
  return storage::DecodeLabelMeta(record).base;
}

}  // namespace

const LayerKindOps kLabelKind{.kind = LayerKind::kLabel, .create = Create, .meta = Meta, .probability = Probability,
                              .statistics = Statistics, .export_own = ExportOwn, .occupancy_base = OccupancyBase};

}  // namespace anchordb::services::grid_detail
