#pragma once
// PNG decoding and encoding with libspng (Debian libspng-dev): the depth, mask and map images of the API. libspng
// replaced OpenCV's imgcodecs here, whose Debian build loads GDAL and about 140 shared libraries into every process
// (0.45 s of each start of a server or test binary).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anchordb::engine {

// Rows top to bottom, channels interleaved in the file's order (grey, grey + alpha, RGB, RGBA), 16-bit samples in
// host byte order. A palette image decodes to RGBA (its transparency applied), grey of 1, 2 or 4 bits to 8-bit grey.
struct PngImage {
  int width = 0, height = 0;
  int channels = 0;   // 1, 2, 3 or 4
  int bit_depth = 0;  // 8 or 16
  std::vector<std::uint8_t> bytes;  // width * height * channels * bit_depth / 8

  std::size_t row_bytes() const { return static_cast<std::size_t>(width) * channels * (bit_depth / 8); }
};

// The (width, height) an IHDR header declares, as written (not range-checked), read without decoding; nullopt when
// `png` does not start with the PNG signature and an IHDR chunk. Callers bound the size with it before decoding.
std::optional<std::pair<std::uint32_t, std::uint32_t>> PngHeaderSize(std::string_view png);

// nullopt when `png` is not a PNG or is damaged anywhere (CRC, zlib stream, truncated data); *why says what, when
// given. The caller bounds the size first (PngHeaderSize): this allocates width x height.
std::optional<PngImage> DecodePngImage(std::string_view png, std::string* why = nullptr);

// A PNG of `image` (channels 1-4, bit depth 8 or 16, bytes of the right size), zlib level `compression_level` (0-9).
// Throws std::invalid_argument on a malformed image.
std::string EncodePngImage(const PngImage& image, int compression_level = 1);

}  // namespace anchordb::engine
