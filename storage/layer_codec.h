#pragma once
// The stored form of each grid layer kind: a storage::LayerRecord holds the kind's typed metadata
// (storage/layer_meta.h, typed columns of the layers row) and a blob.
//  occupancy:   blob u8 {height, width} = the imported image's pixels, image order (row 0 at the top)
//  probability: blob f32 {height, width} = log-odds, cell order (row 0 at the bottom)
//  fused:       no blob (evaluated on read)
//  label:       blob u16 {height, width} = label ids, cell order
// Encoders fill kind, meta and data of a record (never its map, name, version or stamps). Decoders check that the
// record's kind and metadata agree, the metadata's values (sizes, label ids, operands) and the blob's element type
// and shape, and throw Error(kInternal) naming the layer when a row does not match, so a corrupt row is reported,
// never misread.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "schema/types.h"
#include "storage/layer_meta.h"
#include "storage/repositories.h"

namespace anchordb::storage {

struct OccupancyLayer {
  OccupancyLayerMeta meta;
  std::vector<std::uint8_t> image_pixels;  // height x width grey values, image order
};

struct ProbabilityLayer {
  ProbabilityLayerMeta meta;
  std::vector<float> log_odds;  // per cell, cell order
};

struct LabelLayer {
  LabelLayerMeta meta;
  std::vector<std::uint16_t> label_ids;  // per cell, cell order; 0 = no label
};

void EncodeLayer(const OccupancyLayer& layer, LayerRecord& record);
void EncodeLayer(const ProbabilityLayer& layer, LayerRecord& record);
void EncodeLayer(const FusedLayerMeta& meta, LayerRecord& record);
void EncodeLayer(const LabelLayer& layer, LayerRecord& record);

// The metadata alone (the record may have been read without its blob).
GridGeometry DecodeGeometry(const LayerRecord& record);
OccupancyLayerMeta DecodeOccupancyMeta(const LayerRecord& record);
ProbabilityLayerMeta DecodeProbabilityMeta(const LayerRecord& record);
FusedLayerMeta DecodeFusedMeta(const LayerRecord& record);
LabelLayerMeta DecodeLabelMeta(const LayerRecord& record);

// Metadata and cells (the record read with its blob).
OccupancyLayer DecodeOccupancyLayer(const LayerRecord& record);
ProbabilityLayer DecodeProbabilityLayer(const LayerRecord& record);
LabelLayer DecodeLabelLayer(const LayerRecord& record);

}  // namespace anchordb::storage
