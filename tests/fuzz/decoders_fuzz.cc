// libFuzzer target for the decoders that read bytes from clients or from the database file (SPEC 8): the first
// byte picks the decoder, the rest is its input. A decoder may refuse its input with anchordb::Error; anything
// else (a crash, another exception, a sanitizer report, a leak) is a finding.
//   blob codec (storage rows) | depth PNG | mask PNG | raw depth | map_server YAML | map image (PGM/PNG) |
//   JSON object + pose / polygons / log-odds parameters | ISO 8601 times | furniture-graph hypotheses blob |
//   layer record of any kind, whole or metadata only (selector + grid size + metadata alternative + blob, see stored_codecs.h) |
//   OctoMap .bt | OctoMap .ot | point cloud (PCD ascii / binary / binary_compressed, PLY)
// Inputs: the committed corpus tests/fuzz/corpus/decoders (see README.md).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "engine/cloud/cloud_io.h"
#include "engine/grid/map_server.h"
#include "engine/octomap/occupancy_tree.h"
#include "engine/scene/depth_image.h"
#include "schema/error.h"
#include "schema/json_io.h"
#include "storage/blob_codec.h"
#include "tests/fuzz/stored_codecs.h"

namespace {

using namespace anchordb;

void Decode(std::uint8_t which, std::string_view in) {
  switch (which % 10) {
    case 0: {
      const storage::DecodedBlob b = storage::DecodeBlob(in);
      (void)b;
      break;
    }
    case 1: engine::DecodeDepthPng(in, "depth"); break;
    case 2: engine::DecodeMaskPng(in, "mask"); break;
    case 3: engine::DecodeDepthRaw(in, 8, 6, "depth"); break;
    case 4: engine::ParseMapServerYaml(in); break;
    case 5: engine::DecodeMapImage(in, 1 << 20); break;
    case 6: {
      const json::Json j = json::ParseObject(in);
      if (j.contains("pose")) json::AsPose3(j["pose"], "pose");
      if (j.contains("stimulus")) json::AsPolygons(j["stimulus"], "stimulus", 16, 64);
      if (j.contains("params")) json::AsLogOddsParams(j["params"], "params");
      if (j.contains("stamp")) json::AsStampNs(j["stamp"], "stamp");
      break;
    }
    case 7: json::ParseIso8601Ns(in); break;
    case 8: {
      const auto set = fuzz::hypotheses_codec::DecodeHypotheses(fuzz::FuzzGraph(), in);
      (void)set;
      break;
    }
    case 9: {
      const fuzz::LayerInput layer = fuzz::SplitLayerInput(in);
      const storage::LayerRecord record = layer.Record();
      namespace lc = fuzz::layer_codec;
      switch (layer.decoder()) {
        case fuzz::LayerDecoder::kOccupancyLayer: (void)lc::DecodeOccupancyLayer(record); break;
        case fuzz::LayerDecoder::kProbabilityLayer: (void)lc::DecodeProbabilityLayer(record); break;
        case fuzz::LayerDecoder::kLabelLayer: (void)lc::DecodeLabelLayer(record); break;
        case fuzz::LayerDecoder::kFusedMeta: (void)lc::DecodeFusedMeta(record); break;
        case fuzz::LayerDecoder::kOccupancyMeta: (void)lc::DecodeOccupancyMeta(record); break;
        case fuzz::LayerDecoder::kProbabilityMeta: (void)lc::DecodeProbabilityMeta(record); break;
        case fuzz::LayerDecoder::kLabelMeta: (void)lc::DecodeLabelMeta(record); break;
        case fuzz::LayerDecoder::kGeometry: (void)lc::DecodeGeometry(record); break;
      }
      break;
    }
    case 10: {
      engine::OccupancyTree tree;
      tree.ReadBt(in, 1);
      (void)tree.Metadata();
      break;
    }
    case 11: {
      engine::OccupancyTree tree;
      tree.ReadOt(in, 1);
      (void)tree.Metadata();
      break;
    }
    case 12: (void)engine::DecodeCloud(in, 1 << 16); break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    Decode(data[0], std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
  } catch (const anchordb::Error&) {
    // a refusal with a clear error: what bad input should get
  }
  return 0;
}
