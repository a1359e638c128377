#include "engine/scene/depth_image.h"

#include <cstring>

#include "engine/image/png_codec.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace {

PngImage DecodePng(std::string_view bytes, const std::string& field) {
  const auto size = PngSize(bytes);
  if (!size) throw Error(ErrorCode::kInvalidArgument, field + ": not a PNG image", field);
  // The header's size decides before anything is allocated: a few bytes may declare gigapixels.
  if (static_cast<std::uint64_t>(size->first) * static_cast<std::uint64_t>(size->second) > kMaxPngPixels) {
    throw Error(ErrorCode::kPayloadTooLarge,
                field + ": the PNG declares " + std::to_string(size->first) + "x" + std::to_string(size->second) +
                    " pixels, more than " + std::to_string(kMaxPngPixels),
                field);
  }
  std::string why;
  std::optional<PngImage> png = DecodePngImage(bytes, &why);
  if (!png) throw Error(ErrorCode::kInvalidArgument, field + ": the PNG could not be decoded (" + why + ")", field);
  return std::move(*png);
}

std::string Encode(const void* pixels, std::size_t size_bytes, int width, int height, int bit_depth) {
  PngImage image{width, height, 1, bit_depth, {}};
  image.bytes.resize(size_bytes);  // EncodePngImage refuses a size that does not fit width x height
  if (size_bytes > 0) std::memcpy(image.bytes.data(), pixels, size_bytes);
  return EncodePngImage(image, 1);
}

}  // namespace

std::optional<std::pair<int, int>> PngSize(std::string_view bytes) {
  const auto size = PngHeaderSize(bytes);
  if (!size) return std::nullopt;
  const auto [w, h] = *size;
  if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu) return std::nullopt;  // the PNG spec's range
  return std::pair<int, int>(static_cast<int>(w), static_cast<int>(h));
}

DepthImage DecodeDepthPng(std::string_view bytes, const std::string& field) {
  const PngImage m = DecodePng(bytes, field);
  if (m.bit_depth != 16 || m.channels != 1) {
    throw Error(ErrorCode::kInvalidArgument,
                field + ": depth must be a 16-bit single-channel PNG (16UC1, millimetres); got " +
                    std::to_string(m.bit_depth) + "-bit with " + std::to_string(m.channels) + " channel(s)",
                field);
  }
  DepthImage d{m.width, m.height, std::vector<std::uint16_t>(static_cast<std::size_t>(m.width) * m.height)};
  std::memcpy(d.pixels.data(), m.bytes.data(), m.bytes.size());
  return d;
}

DepthImage DecodeDepthRaw(std::string_view bytes, int width, int height, const std::string& field) {
  const std::size_t expected = static_cast<std::size_t>(width) * height * 2;
  if (bytes.size() != expected) {
    throw Error(ErrorCode::kInvalidArgument,
                field + ": raw depth must be " + std::to_string(expected) + " bytes (" + std::to_string(width) + "x" +
                    std::to_string(height) + " little-endian uint16); got " + std::to_string(bytes.size()),
                field);
  }
  DepthImage d{width, height, std::vector<std::uint16_t>(static_cast<std::size_t>(width) * height)};
  std::memcpy(d.pixels.data(), bytes.data(), expected);
  return d;
}

MaskImage DecodeMaskPng(std::string_view bytes, const std::string& field) {
  const PngImage m = DecodePng(bytes, field);
  if (m.bit_depth != 8 || m.channels != 1) {
    throw Error(ErrorCode::kInvalidArgument, field + ": the mask must be an 8-bit single-channel PNG", field);
  }
  MaskImage out{m.width, m.height, std::vector<std::uint8_t>(m.bytes.size())};
  for (std::size_t i = 0; i < m.bytes.size(); ++i) out.pixels[i] = m.bytes[i] ? 1 : 0;
  return out;
}

std::string EncodeDepthPng(const std::vector<std::uint16_t>& pixels, int width, int height) {
  return Encode(pixels.data(), pixels.size() * 2, width, height, 16);
}

std::string EncodeMaskPng(const std::vector<std::uint8_t>& mask, int width, int height) {
  std::vector<std::uint8_t> m(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i) m[i] = mask[i] ? 255 : 0;
  return Encode(m.data(), m.size(), width, height, 8);
}

std::string EncodeGreyPng(const std::vector<std::uint8_t>& grey, int width, int height) {
  return Encode(grey.data(), grey.size(), width, height, 8);
}

}  // namespace anchordb::engine
