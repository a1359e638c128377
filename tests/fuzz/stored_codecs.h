#pragma once
// The stored-form codecs of storage/ that anchordb_fuzz_decoders reaches besides the blob codec (furniture-graph
// hypotheses, layer records), named in this one header (and their sources in one list,
// ANCHORDB_FUZZ_STORED_CODEC_SOURCES in CMakeLists.txt) so that moving them to another folder or namespace is a
// change here and there only. Also the inputs both the target and the seed writer need: the furniture graph every
// hypotheses blob is decoded against, and the layout of a layer-record input.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/grounding/furniture_graph.h"
#include "engine/grounding/grounding.h"
#include "services/furniture/hypotheses_records.h"  // EncodeHypotheses, DecodeHypotheses (engine types)
#include "storage/layer_codec.h"        // EncodeLayer, Decode*Meta, Decode*Layer, DecodeGeometry
#include "storage/repositories.h"       // LayerRecord

namespace anchordb::fuzz {

namespace hypotheses_codec = ::anchordb::services;
namespace layer_codec = ::anchordb::storage;

// Three pieces seen from the origin, two edges, with the built-in category table.
inline const engine::grounding::FurnitureGraph& FuzzGraph() {
  static const engine::grounding::FurnitureGraph graph = [] {
    namespace g = engine::grounding;
    const int k = static_cast<int>(g::DefaultKnowledge().categories.size());
    const auto piece = [k](const std::string& id, double x, double y, int category) {
      g::FurnitureInput in;
      in.id = id;
      in.position_m = {x, y};
      in.extent_m = {0.6, 0.6};
      in.category.assign(static_cast<std::size_t>(k), 0.2 / (k - 1));
      in.category[static_cast<std::size_t>(category % k)] = 0.8;
      return in;
    };
    return g::BuildFurnitureGraph({}, {piece("a", 2.0, 0.0, 0), piece("b", 2.0, 1.0, 1), piece("c", 3.0, 0.0, 2)}, k,
                                  g::GraphParams{});
  }();
  return graph;
}

// Which layer decoder a layer-record input is read with (byte 0 of the input % 8), and the stored kind the record
// gets: the kind that decoder expects, or for kGeometry (which reads any kind) (byte 0 / 8) % 4. Values 0-3 are
// the whole-record decoders of the kinds with a blob and the fused kind's metadata (a fused layer has no blob).
enum class LayerDecoder : std::uint8_t {
  kOccupancyLayer = 0,    // DecodeOccupancyLayer
  kProbabilityLayer = 1,  // DecodeProbabilityLayer
  kLabelLayer = 2,        // DecodeLabelLayer
  kFusedMeta = 3,         // DecodeFusedMeta
  kOccupancyMeta = 4,     // DecodeOccupancyMeta (the record read without its blob)
  kProbabilityMeta = 5,   // DecodeProbabilityMeta
  kLabelMeta = 6,         // DecodeLabelMeta
  kGeometry = 7,          // DecodeGeometry
};

inline LayerKind KindDecodedBy(std::uint8_t selector) {
  switch (static_cast<LayerDecoder>(selector % 8)) {
    case LayerDecoder::kOccupancyLayer:
    case LayerDecoder::kOccupancyMeta: return LayerKind::kOccupancy;
    case LayerDecoder::kProbabilityLayer:
    case LayerDecoder::kProbabilityMeta: return LayerKind::kProbability;
    case LayerDecoder::kLabelLayer:
    case LayerDecoder::kLabelMeta: return LayerKind::kLabel;
    case LayerDecoder::kFusedMeta: return LayerKind::kFused;
    case LayerDecoder::kGeometry: break;
  }
  return static_cast<LayerKind>((selector / 8) % 4);
}

// A layer-record input: byte 0 the decoder selector (LayerDecoder), bytes 1-4 the grid's width and height in cells
// (two signed 16-bit integers, little-endian), byte 5 which metadata alternative the record holds (% 4, in the order
// of storage::StoredLayerMeta: it may disagree with the kind), then the blob. The metadata's other values are fixed:
// since migration 0019 they are typed columns that the database checks, not bytes a decoder parses.
struct LayerInput {
  std::uint8_t selector = 0;
  int width_cells = 0;
  int height_cells = 0;
  std::uint8_t alternative = 0;
  std::string blob;

  LayerDecoder decoder() const { return static_cast<LayerDecoder>(selector % 8); }
  // The record as the repository would return it (name, kind, metadata, blob).
  storage::LayerRecord Record() const {
    storage::LayerRecord record;
    record.name = "fuzzed";
    record.kind = KindDecodedBy(selector);
    GridGeometry g;
    g.width_cells = width_cells;
    g.height_cells = height_cells;
    switch (alternative % 4) {
      case 0: record.meta = storage::OccupancyLayerMeta{g, {}, {"frame_id"}}; break;
      case 1: record.meta = storage::ProbabilityLayerMeta{g, "floor", {}, 2}; break;
      case 2: record.meta = storage::FusedLayerMeta{g, FuseOp::kAndNot, {{"floor", 0.5}}}; break;
      default: record.meta = storage::LabelLayerMeta{g, "floor", {{1, "kitchen"}}}; break;
    }
    record.data = blob;
    return record;
  }
};

inline LayerInput SplitLayerInput(std::string_view in) {
  LayerInput out;
  if (in.size() < 6) return out;
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(in[i]); };
  out.selector = byte(0);
  out.width_cells = static_cast<std::int16_t>(byte(1) | (byte(2) << 8));
  out.height_cells = static_cast<std::int16_t>(byte(3) | (byte(4) << 8));
  out.alternative = byte(5);
  out.blob = std::string(in.substr(6));
  return out;
}

inline std::string JoinLayerInput(std::uint8_t selector, const GridGeometry& g, std::size_t alternative,
                                  const std::string& blob) {
  if (g.width_cells > 0x7fff || g.height_cells > 0x7fff) throw std::length_error("a grid larger than a layer input can hold");
  std::string out;
  out.push_back(static_cast<char>(selector));
  for (const int v : {g.width_cells, g.height_cells}) {
    out.push_back(static_cast<char>(v & 0xff));
    out.push_back(static_cast<char>((v >> 8) & 0xff));
  }
  out.push_back(static_cast<char>(alternative));
  return out + blob;
}

}  // namespace anchordb::fuzz
