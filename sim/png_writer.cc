#include "sim/png_writer.h"

#include <array>
#include <cstring>
#include <stdexcept>

namespace anchordb::sim {
namespace {

std::uint32_t Crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xffu] ^ (crc >> 8);
  return ~crc;
}

void Put32(std::string& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xffu));
}

void Chunk(std::string& out, const char type[4], const std::string& data) {
  Put32(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out += body;
  Put32(out, Crc32(reinterpret_cast<const std::uint8_t*>(body.data()), body.size()));
}

}  // namespace

std::string WritePng(const std::vector<std::uint8_t>& pixels, int width, int height, int channels, int bit_depth) {
  static constexpr char kColourType[5] = {0, 0, 4, 2, 6};
  if (width < 1 || height < 1 || channels < 1 || channels > 4 || (bit_depth != 8 && bit_depth != 16)) {
    throw std::invalid_argument("WritePng: bad size, channels or bit depth");
  }
  const std::size_t sample = static_cast<std::size_t>(bit_depth / 8);
  const std::size_t row = static_cast<std::size_t>(width) * channels * sample;
  if (pixels.size() != row * static_cast<std::size_t>(height)) throw std::invalid_argument("WritePng: pixels do not fit");
  // The scanlines: filter byte 0, then the samples, 16-bit ones big-endian.
  std::string raw;
  raw.reserve((row + 1) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    const std::uint8_t* p = pixels.data() + row * static_cast<std::size_t>(y);
    if (sample == 1) {
      raw.append(reinterpret_cast<const char*>(p), row);
    } else {
      for (std::size_t i = 0; i < row; i += 2) {
        std::uint16_t v;
        std::memcpy(&v, p + i, 2);
        raw.push_back(static_cast<char>(v >> 8));
        raw.push_back(static_cast<char>(v & 0xffu));
      }
    }
  }
  // zlib stream: header, stored blocks of at most 65535 bytes, Adler-32.
  std::string z = {0x78, 0x01};
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) a = (a + c) % 65521u, b = (b + a) % 65521u;
  for (std::size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    const bool last = at + n >= raw.size();
    z.push_back(static_cast<char>(last ? 1 : 0));
    z.push_back(static_cast<char>(n & 0xffu));
    z.push_back(static_cast<char>(n >> 8));
    z.push_back(static_cast<char>(~n & 0xffu));
    z.push_back(static_cast<char>((~n >> 8) & 0xffu));
    z.append(raw, at, n);
    if (last) break;
  }
  Put32(z, (b << 16) | a);
  std::string out = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  Put32(ihdr, static_cast<std::uint32_t>(width));
  Put32(ihdr, static_cast<std::uint32_t>(height));
  ihdr.push_back(static_cast<char>(bit_depth));
  ihdr.push_back(kColourType[channels]);
  ihdr.append(3, '\0');  // deflate, adaptive filtering, no interlace
  Chunk(out, "IHDR", ihdr);
  Chunk(out, "IDAT", z);
  Chunk(out, "IEND", "");
  return out;
}

std::string WritePngGrey16(const std::vector<std::uint16_t>& pixels, int width, int height) {
  std::vector<std::uint8_t> bytes(pixels.size() * 2);
  std::memcpy(bytes.data(), pixels.data(), bytes.size());
  return WritePng(bytes, width, height, 1, 16);
}

}  // namespace anchordb::sim
