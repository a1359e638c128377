#include "storage/layer_codec.h"

#include <cmath>
#include <cstring>

#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::storage {

namespace {

Error Malformed(const LayerRecord& record, const std::string& what) {
  return Error(ErrorCode::kInternal, "stored metadata of layer '" + record.name + "' is malformed: " + what);
}

void CheckGeometry(const LayerRecord& record, const GridGeometry& g) {
  if (g.width_cells < 0 || g.height_cells < 0) throw Malformed(record, "negative grid size");
  if (!std::isfinite(g.resolution_m) || g.resolution_m <= 0) throw Malformed(record, "resolution is not positive");
}

// The metadata of `record`, which must be of `kind` (and hold that kind's alternative).
template <typename Meta>
const Meta& MetaOf(const LayerRecord& record, LayerKind kind) {
  if (record.kind != kind) {
    throw Error(ErrorCode::kInternal, "layer '" + record.name + "' is a " + LayerKindName(record.kind) +
                                          " layer, not a " + LayerKindName(kind) + " layer");
  }
  const Meta* meta = std::get_if<Meta>(&record.meta);
  if (!meta) throw Malformed(record, "the metadata is not of its kind");
  CheckGeometry(record, meta->geometry);
  return *meta;
}

std::vector<std::uint32_t> GridShape(const GridGeometry& g) {
  return {static_cast<std::uint32_t>(g.height_cells), static_cast<std::uint32_t>(g.width_cells)};
}

template <typename T>
std::vector<T> DecodeCells(const LayerRecord& record, BlobElement element, const GridGeometry& g) {
  const DecodedBlob blob = DecodeBlob(record.data);
  if (blob.element != element || blob.shape.size() != 2 || static_cast<int>(blob.shape[0]) != g.height_cells ||
      static_cast<int>(blob.shape[1]) != g.width_cells || blob.bytes.size() != g.CellCount() * sizeof(T)) {
    throw Error(ErrorCode::kInternal, "stored data of layer '" + record.name + "' does not match its metadata");
  }
  std::vector<T> cells(g.CellCount());
  std::memcpy(cells.data(), blob.bytes.data(), blob.bytes.size());
  return cells;
}

template <typename T>
void CheckCellCount(const std::vector<T>& cells, const GridGeometry& g) {
  if (cells.size() != g.CellCount()) throw Error(ErrorCode::kInternal, "layer cells do not match the layer's geometry");
}

}  // namespace

// ---------------------------------------------------------------- encoders

void EncodeLayer(const OccupancyLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.image_pixels, layer.meta.geometry);
  record.kind = LayerKind::kOccupancy;
  record.meta = layer.meta;
  record.data = EncodeBlob(BlobElement::kU8, GridShape(layer.meta.geometry), AsBytes(layer.image_pixels));
}

void EncodeLayer(const ProbabilityLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.log_odds, layer.meta.geometry);
  record.kind = LayerKind::kProbability;
  record.meta = layer.meta;
  // Level 1: observation updates rewrite this blob on every call; speed matters more than the last percent.
  record.data = EncodeBlob(BlobElement::kF32, GridShape(layer.meta.geometry), AsBytes(layer.log_odds), 1);
}

void EncodeLayer(const FusedLayerMeta& meta, LayerRecord& record) {
  record.kind = LayerKind::kFused;
  record.meta = meta;
  record.data.clear();
}

void EncodeLayer(const LabelLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.label_ids, layer.meta.geometry);
  record.kind = LayerKind::kLabel;
  record.meta = layer.meta;
  record.data = EncodeBlob(BlobElement::kU16, GridShape(layer.meta.geometry), AsBytes(layer.label_ids));
}

// ---------------------------------------------------------------- decoders

GridGeometry DecodeGeometry(const LayerRecord& record) {
  const GridGeometry geometry = std::visit([](const auto& meta) { return meta.geometry; }, record.meta);
  if (static_cast<std::size_t>(record.kind) != record.meta.index()) throw Malformed(record, "the metadata is not of its kind");
  CheckGeometry(record, geometry);
  return geometry;
}

OccupancyLayerMeta DecodeOccupancyMeta(const LayerRecord& record) {
  return MetaOf<OccupancyLayerMeta>(record, LayerKind::kOccupancy);
}

ProbabilityLayerMeta DecodeProbabilityMeta(const LayerRecord& record) {
  const ProbabilityLayerMeta& meta = MetaOf<ProbabilityLayerMeta>(record, LayerKind::kProbability);
  if (meta.observations < 0) throw Malformed(record, "negative observation count");
  return meta;
}

FusedLayerMeta DecodeFusedMeta(const LayerRecord& record) {
  const FusedLayerMeta& meta = MetaOf<FusedLayerMeta>(record, LayerKind::kFused);
  if (meta.operands.empty()) throw Malformed(record, "a fused layer without operands");
  return meta;
}

LabelLayerMeta DecodeLabelMeta(const LayerRecord& record) {
  const LabelLayerMeta& meta = MetaOf<LabelLayerMeta>(record, LayerKind::kLabel);
  for (const auto& [id, name] : meta.labels) {
    if (id < 1 || id > 65535) throw Malformed(record, "label id " + std::to_string(id) + " outside 1..65535");
  }
  return meta;
}

OccupancyLayer DecodeOccupancyLayer(const LayerRecord& record) {
  OccupancyLayer layer{DecodeOccupancyMeta(record), {}};
  layer.image_pixels = DecodeCells<std::uint8_t>(record, BlobElement::kU8, layer.meta.geometry);
  return layer;
}

ProbabilityLayer DecodeProbabilityLayer(const LayerRecord& record) {
  ProbabilityLayer layer{DecodeProbabilityMeta(record), {}};
  layer.log_odds = DecodeCells<float>(record, BlobElement::kF32, layer.meta.geometry);
  return layer;
}

LabelLayer DecodeLabelLayer(const LayerRecord& record) {
  LabelLayer layer{DecodeLabelMeta(record), {}};
  layer.label_ids = DecodeCells<std::uint16_t>(record, BlobElement::kU16, layer.meta.geometry);
  return layer;
}

}  // namespace anchordb::storage
