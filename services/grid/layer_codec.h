#pragma once
// How each layer kind is kept in a storage::LayerRecord (meta JSON + blob) and turned back into engine grids.
//  occupancy:   meta {geometry, map_server{...}}, blob u8 {height, width} = the imported image pixels, image order
//  probability: meta {geometry, base, log_odds{...}, observations}, blob f32 {height, width} log-odds, cell order
//  fused:       meta {geometry, op, operands[{layer, threshold}]}, no blob (evaluated on read)
//  label:       meta {geometry, base, labels{"1": "kitchen"}}, blob u16 {height, width} label ids, cell order
#include <string>

#include "engine/grid/grid.h"
#include "engine/grid/map_server.h"
#include "schema/json_io.h"
#include "storage/repositories.h"

namespace anchordb::services::detail {

using json::Json;

struct OccupancyLayer {
  engine::GreyImage image;
  MapServerMeta meta;
  engine::OccupancyGrid grid;
};

Json ParseMeta(const storage::LayerRecord& record);
GridGeometry GeometryFromMeta(const Json& meta);
Json MapServerMetaToJson(const MapServerMeta& meta);
MapServerMeta MapServerMetaFromJson(const Json& j);

std::string EncodeImageBlob(const engine::GreyImage& image);
std::string EncodeLogOddsBlob(const engine::LogOddsGrid& grid);
std::string EncodeLabelBlob(const engine::LabelGrid& grid);

OccupancyLayer DecodeOccupancy(const storage::LayerRecord& record);
engine::LogOddsGrid DecodeLogOdds(const storage::LayerRecord& record);
engine::LabelGrid DecodeLabels(const storage::LayerRecord& record);

// Loads a layer (with data) or throws kNotFound naming it.
storage::LayerRecord RequireLayer(storage::Connection& c, const std::string& map, const std::string& layer);
void RequireMap(storage::Connection& c, const std::string& map);

// Any layer as per-cell probabilities: occupancy value/100 (unknown 0.5), probability from log-odds,
// fused as 0/1, label as 1 where any label is set.
engine::ProbabilityGrid EvaluateProbability(storage::Connection& c, const storage::LayerRecord& record, int depth = 0);

}  // namespace anchordb::services::detail
