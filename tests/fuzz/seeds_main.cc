// Writes the seeds of anchordb_fuzz_decoders into a directory: valid inputs of every decoder, made with the
// project's own encoders. The first byte selects the decoder (decoders_fuzz.cc). The seeds are committed in
// tests/fuzz/corpus/decoders; rerun this (same names, same bytes) when an encoder's format changes:
//   build-fuzz/anchordb_fuzz_seeds tests/fuzz/corpus/decoders
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include "engine/grid/map_server.h"
#include "engine/scene/depth_image.h"
#include "storage/blob_codec.h"
#include "tests/fuzz/api_codecs.h"

using namespace anchordb;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  int n = 0;
  const auto put = [&](std::uint8_t which, const std::string& name, const std::string& body) {
    std::ofstream(dir / ("seed-" + name), std::ios::binary) << static_cast<char>(which) << body;
    ++n;
  };
  // A seed the decoder refuses would only test the refusal: the api-side seeds are decoded back here first.
  const auto decodes = [](const std::string& input, std::size_t expected_cells) {
    const fuzz::LayerInput in = fuzz::SplitLayerInput(input);
    storage::LayerRecord record;
    record.meta_json = in.meta_json;
    record.data = in.blob;
    const std::size_t cells = in.kind == 0   ? fuzz::layer_codec::DecodeOccupancy(record).grid.cells.size()
                              : in.kind == 1 ? fuzz::layer_codec::DecodeLogOdds(record).cells.size()
                              : in.kind == 2 ? fuzz::layer_codec::DecodeLabels(record).cells.size()
                                             : fuzz::layer_codec::ParseMeta(record).size();
    if (cells != expected_cells) throw std::logic_error("a layer seed does not decode to what was encoded");
    return input;
  };
  std::vector<std::uint16_t> depth(8 * 6);
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = static_cast<std::uint16_t>(1000 + 37 * i);
  put(0, "blob-u16-delta", storage::EncodeBlob(storage::BlobElement::kU16, {6, 8}, storage::AsBytes(depth), 3,
                                               storage::BlobFilter::kDeltaShuffle16));
  std::vector<float> metres(8 * 6, 1.5f);
  put(0, "blob-f32", storage::EncodeBlob(storage::BlobElement::kF32, {6, 8}, storage::AsBytes(metres)));
  put(1, "depth-png", engine::EncodeDepthPng(depth, 8, 6));
  std::vector<std::uint8_t> mask(8 * 6, 0);
  mask[7] = mask[20] = 1;
  put(2, "mask-png", engine::EncodeMaskPng(mask, 8, 6));
  put(3, "depth-raw", std::string(reinterpret_cast<const char*>(depth.data()), depth.size() * 2));
  MapServerMeta meta;
  meta.image = "map.pgm";
  put(4, "map-yaml", engine::EmitMapServerYaml(meta));
  engine::GreyImage grey{8, 6, std::vector<std::uint8_t>(48, 254)};
  grey.pixels[9] = 0;
  put(5, "map-pgm", engine::EncodePgm(grey));
  put(5, "map-png", engine::EncodePng(grey));
  put(6, "json-pose", R"({"pose":{"position":[1,2,0],"orientation":[0,0,0.7071068,0.7071068]},"stimulus":[[[0,0],[1,0],[1,1]]],)"
                      R"("stamp":"2026-11-23T05:30:07.250Z"})");
  put(6, "json-params", R"({"params":{"hit":0.7,"miss":0.4,"clamp_min":0.12,"clamp_max":0.97},"stamp":1795411807000000000})");
  put(7, "iso8601", "2026-11-23T05:30:07+01:00");

  // Furniture-graph hypotheses: the graph as seen, and after one description.
  namespace g = engine::grounding;
  const g::FurnitureGraph& graph = fuzz::FuzzGraph();
  const g::HypothesisSet initial = g::InitialHypotheses(graph);
  g::GroundingParams params;
  params.n_best = 6;
  const g::Description said{0, g::Relation::kLeftOf, 1};
  const g::HypothesisSet grounded = g::Ground(graph, g::DefaultKnowledge(), initial, said, params);
  for (const auto& [name, set] : {std::pair{"hypotheses-initial", &initial}, std::pair{"hypotheses-grounded", &grounded}}) {
    const std::string blob = fuzz::hypotheses_codec::EncodeHypotheses(graph, *set);
    if (fuzz::hypotheses_codec::DecodeHypotheses(graph, blob).ranked.size() != set->ranked.size()) {
      throw std::logic_error("a hypotheses seed does not decode to what was encoded");
    }
    put(8, name, blob);
  }

  // Layer records as the grid service stores them (meta JSON + blob per kind).
  const json::Json geometry = {{"width_cells", 8}, {"height_cells", 6}, {"resolution_m", 0.1}, {"origin", {-0.4, -0.3, 0.0}}};
  put(9, "layer-occupancy", decodes(
      fuzz::JoinLayerInput(0, json::Json({{"geometry", geometry}, {"map_server", fuzz::layer_codec::MapServerMetaToJson(meta)}}).dump(),
                           fuzz::layer_codec::EncodeImageBlob(grey)), 48));
  engine::LogOddsGrid log_odds;
  log_odds.geometry = fuzz::layer_codec::GeometryFromMeta({{"geometry", geometry}});
  log_odds.cells.assign(48, 0.0f);
  log_odds.cells[5] = 0.85f;
  log_odds.cells[30] = -0.4f;
  put(9, "layer-probability", decodes(
      fuzz::JoinLayerInput(1, json::Json({{"geometry", geometry}, {"base", "floor"},
                                          {"log_odds", {{"hit", 0.7}, {"miss", 0.4}, {"clamp_min", 0.12}, {"clamp_max", 0.97}}}}).dump(),
                           fuzz::layer_codec::EncodeLogOddsBlob(log_odds)), 48));
  engine::LabelGrid labels;
  labels.geometry = log_odds.geometry;
  labels.cells.assign(48, 0);
  labels.cells[10] = labels.cells[11] = 1;
  labels.cells[40] = 2;
  put(9, "layer-label", decodes(
      fuzz::JoinLayerInput(2, json::Json({{"geometry", geometry}, {"base", "floor"}, {"labels", {{"1", "kitchen"}, {"2", "hall"}}}}).dump(),
                           fuzz::layer_codec::EncodeLabelBlob(labels)), 48));
  put(9, "layer-fused-meta", decodes(
      fuzz::JoinLayerInput(3, json::Json({{"geometry", geometry}, {"op", "and_not"},
                                          {"operands", {{{"layer", "floor"}, {"threshold", 0.5}}}}}).dump(), ""), 3));
  std::printf("%d seeds in %s\n", n, dir.c_str());
  return 0;
}
