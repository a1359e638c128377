// Fused layers: a logical operator over thresholded layers of the same map, evaluated on every read.
#include "engine/grid/fusion.h"
#include "engine/grid/layer_values.h"
#include "schema/error.h"
#include "services/grid/layer_kinds.h"

namespace anchordb::services::grid_detail {
namespace {

std::vector<std::string> Create(const MapLayers& layers, const LayerSpec& spec, storage::LayerRecord& record) {
  const auto& s = std::get<FusedLayerSpec>(spec);
  std::optional<GridGeometry> geometry;
  std::vector<std::string> depends;
  for (std::size_t i = 0; i < s.operands.size(); ++i) {
    const GridGeometry g = storage::DecodeGeometry(layers.Require(s.operands[i].layer));
    if (geometry && !(*geometry == g)) {
      throw Error(ErrorCode::kUnprocessable, "operands cover different grids", "operands[" + std::to_string(i) + "]");
    }
    geometry = g;
    depends.push_back(s.operands[i].layer);
  }
  if (!geometry) throw Error(ErrorCode::kInvalidArgument, "a fused layer needs operands", "operands");
  storage::EncodeLayer(storage::FusedLayerMeta{*geometry, s.op, s.operands}, record);
  return depends;
}

LayerMeta Meta(const storage::LayerRecord& record) { return storage::DecodeFusedMeta(record); }

engine::ProbabilityGrid Probability(const MapLayers& layers, const storage::LayerRecord& record, int depth) {
  const storage::FusedLayerMeta meta = storage::DecodeFusedMeta(record);
  std::vector<engine::MaskGrid> operands;
  for (const FuseOperand& op : meta.operands) {
    operands.push_back(engine::Threshold(layers.Probability(layers.Require(op.layer), depth + 1), op.threshold));
  }
  return engine::MaskToProbability(engine::Fuse(meta.op, operands));
}

LayerStatistics Statistics(const MapLayers& layers, const storage::LayerRecord& record,
                           const engine::OccupancyThresholds&) {
  return engine::SummariseProbability(layers.Probability(record));
}

std::optional<ExportedLayer> ExportOwn(const storage::LayerRecord&, LayerFormat) { return std::nullopt; }

// The occupancy layer under the first operand. A fused first operand is not followed: its own name is returned
// (and the caller finds it is not an occupancy layer), as before the kind table.
std::string OccupancyBase(const MapLayers& layers, const storage::LayerRecord& record) {
  const storage::LayerRecord first = layers.Require(storage::DecodeFusedMeta(record).operands.at(0).layer);
  return first.kind == LayerKind::kFused ? first.name : layers.OccupancyBase(first);
}

}  // namespace

const LayerKindOps kFusedKind{.kind = LayerKind::kFused, .create = Create, .meta = Meta, .probability = Probability,
                              .statistics = Statistics, .export_own = ExportOwn, .occupancy_base = OccupancyBase};

}  // namespace anchordb::services::grid_detail
