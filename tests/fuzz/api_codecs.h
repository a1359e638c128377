#pragma once
// The api-side codecs that anchordb_fuzz_decoders reaches, named in this one header (and their sources in one list,
// ANCHORDB_FUZZ_API_CODEC_SOURCES in CMakeLists.txt) so that moving them to another folder or namespace is a change
// here and there only. Also the inputs both the target and the seed writer need: the furniture graph every
// hypotheses blob is decoded against, and the layout of a layer-record input.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "services/furniture/furniture_service.h"  // EncodeHypotheses, DecodeHypotheses
#include "services/grid/layer_codec.h"        // ParseMeta, DecodeOccupancy, DecodeLogOdds, DecodeLabels, Encode*Blob
#include "engine/grounding/furniture_graph.h"

namespace anchordb::fuzz {

namespace hypotheses_codec = ::anchordb::services;
namespace layer_codec = ::anchordb::services::detail;

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

// A layer-record input: byte 0 the kind to decode as (% 4: occupancy, probability, label, metadata only), bytes 1-2
// the length n of the metadata JSON (little-endian), then n bytes of metadata, then the blob.
struct LayerInput {
  int kind = 0;
  std::string meta_json;
  std::string blob;
};

inline LayerInput SplitLayerInput(std::string_view in) {
  LayerInput out;
  if (in.size() < 3) return out;
  out.kind = static_cast<std::uint8_t>(in[0]) % 4;
  const std::size_t n = static_cast<std::uint8_t>(in[1]) | (static_cast<std::size_t>(static_cast<std::uint8_t>(in[2])) << 8);
  in.remove_prefix(3);
  out.meta_json = std::string(in.substr(0, n));
  if (n < in.size()) out.blob = std::string(in.substr(n));
  return out;
}

inline std::string JoinLayerInput(int kind, const std::string& meta_json, const std::string& blob) {
  std::string out;
  out.push_back(static_cast<char>(kind));
  out.push_back(static_cast<char>(meta_json.size() & 0xff));
  out.push_back(static_cast<char>((meta_json.size() >> 8) & 0xff));
  return out + meta_json + blob;
}

}  // namespace anchordb::fuzz
