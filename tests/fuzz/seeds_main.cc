// Writes the seed corpus of anchordb_fuzz_decoders into a directory: one valid input per decoder, made with the
// project's own encoders (so no binary files are kept in the repository). The first byte selects the decoder
// (decoders_fuzz.cc).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/grid/map_server.h"
#include "engine/scene/depth_image.h"
#include "storage/blob_codec.h"

using namespace anchordb;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  int n = 0;
  const auto put = [&](std::uint8_t which, const std::string& body) {
    std::ofstream(dir / ("seed-" + std::to_string(n++)), std::ios::binary) << static_cast<char>(which) << body;
  };
  std::vector<std::uint16_t> depth(8 * 6);
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = static_cast<std::uint16_t>(1000 + 37 * i);
  put(0, storage::EncodeBlob(storage::BlobElement::kU16, {6, 8}, storage::AsBytes(depth), 3,
                             storage::BlobFilter::kDeltaShuffle16));
  std::vector<float> metres(8 * 6, 1.5f);
  put(0, storage::EncodeBlob(storage::BlobElement::kF32, {6, 8}, storage::AsBytes(metres)));
  put(1, engine::EncodeDepthPng(depth, 8, 6));
  std::vector<std::uint8_t> mask(8 * 6, 0);
  mask[7] = mask[20] = 1;
  put(2, engine::EncodeMaskPng(mask, 8, 6));
  put(3, std::string(reinterpret_cast<const char*>(depth.data()), depth.size() * 2));
  MapServerMeta meta;
  meta.image = "map.pgm";
  put(4, engine::EmitMapServerYaml(meta));
  engine::GreyImage grey{8, 6, std::vector<std::uint8_t>(48, 254)};
  grey.pixels[9] = 0;
  put(5, engine::EncodePgm(grey));
  put(5, engine::EncodePng(grey));
  put(6, R"({"pose":{"position":[1,2,0],"orientation":[0,0,0.7071068,0.7071068]},"stimulus":[[[0,0],[1,0],[1,1]]],)"
         R"("stamp":"2026-11-23T05:30:07.250Z"})");
  put(6, R"({"params":{"hit":0.7,"miss":0.4,"clamp_min":0.12,"clamp_max":0.97},"stamp":1795411807000000000})");
  put(7, "2026-11-23T05:30:07+01:00");
  std::printf("%d seeds in %s\n", n, dir.c_str());
  return 0;
}
