#pragma once
// The stored form of each grid layer kind: a storage::LayerRecord holds a metadata JSON document and a blob.
//  occupancy:   meta {geometry, map_server{...}, ignored_yaml_keys}, blob u8 {height, width} = the imported image's
//               pixels, image order (row 0 at the top)
//  probability: meta {geometry, base, log_odds{hit, miss, clamp_min, clamp_max}, observations},
//               blob f32 {height, width} = log-odds, cell order (row 0 at the bottom)
//  fused:       meta {geometry, op, operands[{layer, threshold}]}, no blob (evaluated on read)
//  label:       meta {geometry, base, labels{"1": "kitchen"}}, blob u16 {height, width} = label ids, cell order
// Encoders fill kind, meta_json and data of a record (never its map, name, version or stamps). Decoders check the
// record's kind, every metadata field and the blob's element type and shape, and throw Error(kInternal) naming the
// layer when a row does not match this format, so a corrupt row is reported, never misread.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "schema/types.h"
#include "storage/repositories.h"

namespace anchordb::storage {

struct OccupancyLayerMeta {
  GridGeometry geometry;
  MapServerMeta map_server;                    // the YAML values as imported
  std::vector<std::string> ignored_yaml_keys;  // YAML keys map_server does not know
};

struct ProbabilityLayerMeta {
  GridGeometry geometry;
  std::string base;  // the occupancy layer observations are ray-cast on
  LogOddsParams log_odds;
  std::int64_t observations = 0;  // observation updates applied so far
};

struct FusedLayerMeta {
  GridGeometry geometry;
  FuseOp op = FuseOp::kAnd;
  std::vector<FuseOperand> operands;  // layers of the same map, in order
};

struct LabelLayerMeta {
  GridGeometry geometry;
  std::string base;                   // the occupancy layer the labels were drawn over
  std::map<int, std::string> labels;  // label id (1..65535) -> name
};

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

// The stored metadata document alone (what an encoder puts into record.meta_json).
std::string EncodeLayerMeta(const OccupancyLayerMeta& meta);
std::string EncodeLayerMeta(const ProbabilityLayerMeta& meta);
std::string EncodeLayerMeta(const FusedLayerMeta& meta);
std::string EncodeLayerMeta(const LabelLayerMeta& meta);

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
