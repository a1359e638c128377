#pragma once
// A PNG writer of our own for the simulation side (scenario masks, the renderer CLI's files, test images): filter 0
// and stored (uncompressed) deflate blocks, no compression. It shares no code with the server's codec
// (engine/image/png_codec.h, libspng), so what the scenario sends checks that codec rather than agreeing with it.
#include <cstdint>
#include <string>
#include <vector>

namespace anchordb::sim {

// `pixels`: rows top to bottom, channels interleaved (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), bit_depth 8 or 16
// (16-bit samples in host byte order, two bytes each). Throws std::invalid_argument when the sizes do not fit.
std::string WritePng(const std::vector<std::uint8_t>& pixels, int width, int height, int channels, int bit_depth);
std::string WritePngGrey16(const std::vector<std::uint16_t>& pixels, int width, int height);

}  // namespace anchordb::sim
