#pragma once
// Depth and mask images in and out: 16-bit PNG (ROS 16UC1), raw little-endian, 8-bit masks. Throws
// anchordb::Error(kInvalidArgument) naming the problem (wrong bit depth, wrong size, truncated data).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anchordb::engine {

struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> pixels;  // row-major, sensor units, 0 = no measurement
};

struct MaskImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // 0/1
};

// PNGs that declare more pixels than this are refused (kPayloadTooLarge) before anything is allocated.
inline constexpr std::uint64_t kMaxPngPixels = std::uint64_t{1} << 25;  // 32 M (e.g. 8192 x 4096)

// (width, height) from a PNG's header, without decoding; nullopt if `bytes` does not start like a PNG.
std::optional<std::pair<int, int>> PngSize(std::string_view bytes);
// A 16-bit single-channel PNG; an 8-bit or colour PNG is refused (the field is named `field`).
DepthImage DecodeDepthPng(std::string_view bytes, const std::string& field);
// Raw little-endian uint16, row-major; its size must be exactly width * height * 2.
DepthImage DecodeDepthRaw(std::string_view bytes, int width, int height, const std::string& field);
// An 8-bit single-channel PNG; any non-zero pixel counts as set.
MaskImage DecodeMaskPng(std::string_view bytes, const std::string& field);

std::string EncodeDepthPng(const std::vector<std::uint16_t>& pixels, int width, int height);
// 0/1 mask as 0/255 8-bit PNG.
std::string EncodeMaskPng(const std::vector<std::uint8_t>& mask, int width, int height);
std::string EncodeGreyPng(const std::vector<std::uint8_t>& grey, int width, int height);

}  // namespace anchordb::engine
