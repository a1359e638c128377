// Probability layers: log-odds of a semantic cue per cell over an occupancy layer, raised and lowered by
// observations (GridService::Observe).
#include "engine/grid/layer_values.h"
#include "engine/grid/log_odds.h"
#include "services/grid/layer_kinds.h"
#include "storage/blob_codec.h"

namespace anchordb::services::grid_detail {
namespace {

std::vector<std::string> Create(const MapLayers& layers, const LayerSpec& spec, storage::LayerRecord& record) {
  const auto& s = std::get<ProbabilityLayerSpec>(spec);
  const GridGeometry geometry = storage::DecodeGeometry(layers.RequireOccupancy(s.base));
  std::vector<float> log_odds(geometry.CellCount(), 0.0f);  // p = 0.5 everywhere
  storage::EncodeLayer(storage::ProbabilityLayer{{geometry, s.base, s.log_odds, 0}, std::move(log_odds)}, record);
  return {s.base};
}

LayerMeta Meta(const storage::LayerRecord& record) { return storage::DecodeProbabilityMeta(record); }

engine::ProbabilityGrid Probability(const MapLayers&, const storage::LayerRecord& record, int) {
  storage::ProbabilityLayer layer = storage::DecodeProbabilityLayer(record);
  return engine::ToProbability(GridOf(layer.meta.geometry, std::move(layer.log_odds)));
}

LayerStatistics Statistics(const MapLayers& layers, const storage::LayerRecord& record,
                           const engine::OccupancyThresholds&) {
  return engine::SummariseProbability(layers.Probability(record));
}

// raw is the stored log-odds; images and YAML show the probabilities.
std::optional<ExportedLayer> ExportOwn(const storage::LayerRecord& record, LayerFormat format) {
  if (format != LayerFormat::kRaw) return std::nullopt;
  const storage::ProbabilityLayer layer = storage::DecodeProbabilityLayer(record);
  return ExportedLayer{.format = BytesFormat::kRaw, .body = std::string(storage::AsBytes(layer.log_odds)),
                       .element = RawElement::kF32LogOddsCellOrder};
}

std::string OccupancyBase(const MapLayers&, const storage::LayerRecord& record) {
  return storage::DecodeProbabilityMeta(record).base;
}

}  // namespace

const LayerKindOps kProbabilityKind{.kind = LayerKind::kProbability, .create = Create, .meta = Meta, .probability = Probability,
                                    .statistics = Statistics, .export_own = ExportOwn, .occupancy_base = OccupancyBase};

}  // namespace anchordb::services::grid_detail
