// Occupancy layers: a map_server map as imported (YAML values and image pixels), read with map_server's rules.
#include "engine/grid/layer_values.h"
#include "services/grid/layer_kinds.h"

namespace anchordb::services::grid_detail {
namespace {

LayerMeta Meta(const storage::LayerRecord& record) { return storage::DecodeOccupancyMeta(record); }

engine::ProbabilityGrid Probability(const MapLayers&, const storage::LayerRecord& record, int) {
  return engine::OccupancyToProbability(DecodeOccupancyView(record).grid);
}

LayerStatistics Statistics(const MapLayers&, const storage::LayerRecord& record,
                           const engine::OccupancyThresholds& thresholds) {
  return engine::CountOccupancy(DecodeOccupancyView(record).grid, thresholds);
}

// Every format shows the layer as imported: the same pixels, the same YAML values.
std::optional<ExportedLayer> ExportOwn(const storage::LayerRecord& record, LayerFormat format) {
  OccupancyView view = DecodeOccupancyView(record);
  switch (format) {
    case LayerFormat::kPng: return ExportedLayer{.format = BytesFormat::kPng, .body = engine::EncodePng(view.image)};
    case LayerFormat::kPgm: return ExportedLayer{.format = BytesFormat::kPgm, .body = engine::EncodePgm(view.image)};
    case LayerFormat::kYaml:
      view.map_server.image = record.name + ".pgm";
      return ExportedLayer{.format = BytesFormat::kMapServerYaml, .body = engine::EmitMapServerYaml(view.map_server)};
    case LayerFormat::kRaw:
      return ExportedLayer{.format = BytesFormat::kRaw,
                           .body = std::string(view.image.pixels.begin(), view.image.pixels.end()),
                           .element = RawElement::kU8ImageOrder};
  }
  return std::nullopt;
}

std::string OccupancyBase(const MapLayers&, const storage::LayerRecord& record) { return record.name; }

}  // namespace

const LayerKindOps kOccupancyKind{.kind = LayerKind::kOccupancy, .create = nullptr, .meta = Meta, .probability = Probability,
                                  .statistics = Statistics, .export_own = ExportOwn, .occupancy_base = OccupancyBase};

}  // namespace anchordb::services::grid_detail
