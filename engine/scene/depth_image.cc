#include "engine/scene/depth_image.h"

#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

cv::Mat DecodePng(std::string_view bytes, const std::string& field) {
  const auto size = PngSize(bytes);
  if (!size) throw Error(ErrorCode::kInvalidArgument, field + ": not a PNG image", field);
  // The header's size decides before anything is allocated: a few bytes may declare gigapixels.
  if (static_cast<std::uint64_t>(size->first) * static_cast<std::uint64_t>(size->second) > kMaxPngPixels) {
    throw Error(ErrorCode::kPayloadTooLarge,
                field + ": the PNG declares " + std::to_string(size->first) + "x" + std::to_string(size->second) +
                    " pixels, more than " + std::to_string(kMaxPngPixels),
                field);
  }
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data()));
  cv::Mat m = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw Error(ErrorCode::kInvalidArgument, field + ": the PNG could not be decoded", field);
  return m;
}

std::string Encode(const cv::Mat& m) {
  std::vector<std::uint8_t> buf;
  cv::imencode(".png", m, buf, {cv::IMWRITE_PNG_COMPRESSION, 1});
  return std::string(buf.begin(), buf.end());
}

}  // namespace

std::optional<std::pair<int, int>> PngSize(std::string_view bytes) {
  static constexpr unsigned char kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // Signature, then the IHDR chunk: length (4), "IHDR", width (4, big-endian), height (4).
  if (bytes.size() < 24 || std::memcmp(bytes.data(), kPngMagic, 8) != 0 || bytes.substr(12, 4) != "IHDR") {
    return std::nullopt;
  }
  const auto be32 = [&](std::size_t o) {
    return (std::uint32_t(std::uint8_t(bytes[o])) << 24) | (std::uint32_t(std::uint8_t(bytes[o + 1])) << 16) |
           (std::uint32_t(std::uint8_t(bytes[o + 2])) << 8) | std::uint32_t(std::uint8_t(bytes[o + 3]));
  };
  const std::uint32_t w = be32(16), h = be32(20);
  if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu) return std::nullopt;  // the PNG spec's range
  return std::pair<int, int>(static_cast<int>(w), static_cast<int>(h));
}

DepthImage DecodeDepthPng(std::string_view bytes, const std::string& field) {
  const cv::Mat m = DecodePng(bytes, field);
  if (m.depth() != CV_16U || m.channels() != 1) {
    throw Error(ErrorCode::kInvalidArgument,
                field + ": depth must be a 16-bit single-channel PNG (16UC1, millimetres); got " +
                    std::to_string(m.elemSize1() * 8) + "-bit with " + std::to_string(m.channels()) + " channel(s)",
                field);
  }
  DepthImage d{m.cols, m.rows, std::vector<std::uint16_t>(m.total())};
  for (int r = 0; r < m.rows; ++r) std::memcpy(d.pixels.data() + static_cast<std::size_t>(r) * m.cols, m.ptr(r), m.cols * 2);
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
  const cv::Mat m = DecodePng(bytes, field);
  if (m.depth() != CV_8U || m.channels() != 1) {
    throw Error(ErrorCode::kInvalidArgument, field + ": the mask must be an 8-bit single-channel PNG", field);
  }
  MaskImage out{m.cols, m.rows, std::vector<std::uint8_t>(m.total())};
  for (int r = 0; r < m.rows; ++r) {
    const std::uint8_t* row = m.ptr<std::uint8_t>(r);
    for (int c = 0; c < m.cols; ++c) out.pixels[static_cast<std::size_t>(r) * m.cols + c] = row[c] ? 1 : 0;
  }
  return out;
}

std::string EncodeDepthPng(const std::vector<std::uint16_t>& pixels, int width, int height) {
  return Encode(cv::Mat(height, width, CV_16U, const_cast<std::uint16_t*>(pixels.data())));
}

std::string EncodeMaskPng(const std::vector<std::uint8_t>& mask, int width, int height) {
  cv::Mat m(height, width, CV_8U);
  for (std::size_t i = 0; i < mask.size(); ++i) m.data[i] = mask[i] ? 255 : 0;
  return Encode(m);
}

std::string EncodeGreyPng(const std::vector<std::uint8_t>& grey, int width, int height) {
  return Encode(cv::Mat(height, width, CV_8U, const_cast<std::uint8_t*>(grey.data())));
}

}  // namespace anchordb::engine
