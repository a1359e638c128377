#pragma once
// The format of every array stored as a BLOB: a fixed little-endian header, then one zstd frame.
//   bytes 0-3   magic "ADBB"
//   bytes 4-5   format version (1)
//   byte  6     element type (BlobElement)
//   byte  7     number of dimensions n (1..4)
//   byte  8     filter applied before compression (BlobFilter)
//   bytes 9-11  reserved, zero
//   n x u32     shape, outermost first (a grid is {height, width})
//   u64         uncompressed payload size in bytes (= element size x product of shape)
//   ...         zstd frame with content checksum
// Decoding checks all of it and throws Error(kInternal) naming what is wrong, so corrupt rows are reported,
// never silently misread.
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anchordb::storage {

enum class BlobElement : std::uint8_t { kU8 = 1, kI8 = 2, kU16 = 3, kI16 = 4, kF32 = 5, kF64 = 6, kU32 = 7 };

// A reversible transform that makes images compress better.
enum class BlobFilter : std::uint8_t {
  kNone = 0,
  // u16 only: each value minus its left neighbour along the innermost dimension (mod 2^16), then the low bytes
  // of all values followed by the high bytes. Smooth depth images shrink to about a third with zstd.
  kDeltaShuffle16 = 1,
};

std::size_t ElementSize(BlobElement element);

struct DecodedBlob {
  BlobElement element = BlobElement::kU8;
  std::vector<std::uint32_t> shape;
  std::string bytes;  // the raw little-endian payload
};

// `payload` must hold exactly ElementSize(element) x product(shape) bytes. `level` is the zstd level.
std::string EncodeBlob(BlobElement element, const std::vector<std::uint32_t>& shape, std::string_view payload,
                       int level = 3, BlobFilter filter = BlobFilter::kNone);
DecodedBlob DecodeBlob(std::string_view blob);

// The payload of `blob` as values of T, when it holds `element`s (of T's size) and, unless `count` is 0, exactly
// `count` of them; nullopt otherwise (the caller says what did not match).
template <typename T>
std::optional<std::vector<T>> DecodeArray(std::string_view blob, BlobElement element, std::size_t count = 0) {
  const DecodedBlob d = DecodeBlob(blob);
  if (d.element != element || ElementSize(element) != sizeof(T) || d.bytes.size() % sizeof(T) != 0 ||
      (count != 0 && d.bytes.size() != count * sizeof(T))) {
    return std::nullopt;
  }
  std::vector<T> out(d.bytes.size() / sizeof(T));
  std::memcpy(out.data(), d.bytes.data(), d.bytes.size());
  return out;
}

template <typename T>
std::string_view AsBytes(const std::vector<T>& v) {
  return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

}  // namespace anchordb::storage
