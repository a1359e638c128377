#include "storage/blob_codec.h"

#include <zstd.h>

#include <cstring>

#include "schema/error.h"

namespace anchordb::storage {
namespace {

constexpr char kMagic[4] = {'A', 'D', 'B', 'B'};
constexpr std::uint16_t kFormatVersion = 1;

[[noreturn]] void Corrupt(const std::string& what) { throw Error(ErrorCode::kInternal, "corrupt blob: " + what); }

template <typename T>
void Put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // the project targets little-endian machines (x86-64, aarch64)
  out.append(b, sizeof(T));
}

template <typename T>
T Get(std::string_view in, std::size_t& pos) {
  if (pos + sizeof(T) > in.size()) Corrupt("header is truncated");
  T v;
  std::memcpy(&v, in.data() + pos, sizeof(T));
  pos += sizeof(T);
  return v;
}

std::string DeltaShuffle16(std::string_view in, std::size_t row) {
  const std::size_t n = in.size() / 2;
  std::string out(in.size(), '\0');
  std::uint16_t prev = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint16_t v;
    std::memcpy(&v, in.data() + 2 * i, 2);
    if (i % row == 0) prev = 0;
    const std::uint16_t d = static_cast<std::uint16_t>(v - prev);
    prev = v;
    out[i] = static_cast<char>(d & 0xff);
    out[n + i] = static_cast<char>(d >> 8);
  }
  return out;
}

void UndoDeltaShuffle16(std::string& bytes, std::size_t row) {
  const std::size_t n = bytes.size() / 2;
  std::string out(bytes.size(), '\0');
  std::uint16_t prev = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % row == 0) prev = 0;
    const std::uint16_t d = static_cast<std::uint16_t>(static_cast<std::uint8_t>(bytes[i]) |
                                                       (static_cast<std::uint8_t>(bytes[n + i]) << 8));
    const std::uint16_t v = static_cast<std::uint16_t>(prev + d);
    prev = v;
    std::memcpy(out.data() + 2 * i, &v, 2);
  }
  bytes.swap(out);
}

}  // namespace

std::size_t ElementSize(BlobElement e) {
  switch (e) {
    case BlobElement::kU8:
    case BlobElement::kI8: return 1;
    case BlobElement::kU16:
    case BlobElement::kI16: return 2;
    case BlobElement::kF32:
    case BlobElement::kU32: return 4;
    case BlobElement::kF64: return 8;
  }
  return 0;
}

std::string EncodeBlob(BlobElement element, const std::vector<std::uint32_t>& shape, std::string_view payload, int level,
                       BlobFilter filter) {
  if (shape.empty() || shape.size() > 4) throw Error(ErrorCode::kInternal, "blob shape must have 1-4 dimensions");
  std::uint64_t expected = ElementSize(element);
  for (auto d : shape) expected *= d;
  if (expected != payload.size()) throw Error(ErrorCode::kInternal, "blob payload size does not match its shape");
  std::string filtered;
  if (filter == BlobFilter::kDeltaShuffle16) {
    if (element != BlobElement::kU16 && element != BlobElement::kI16) {
      throw Error(ErrorCode::kInternal, "the delta-shuffle filter applies to 16-bit elements only");
    }
    filtered = DeltaShuffle16(payload, shape.back() == 0 ? 1 : shape.back());
    payload = filtered;
  }
  std::string out(kMagic, 4);
  Put<std::uint16_t>(out, kFormatVersion);
  Put<std::uint8_t>(out, static_cast<std::uint8_t>(element));
  Put<std::uint8_t>(out, static_cast<std::uint8_t>(shape.size()));
  Put<std::uint8_t>(out, static_cast<std::uint8_t>(filter));
  Put<std::uint8_t>(out, 0);
  Put<std::uint16_t>(out, 0);
  for (auto d : shape) Put<std::uint32_t>(out, d);
  Put<std::uint64_t>(out, payload.size());
  const std::size_t header = out.size();
  out.resize(header + ZSTD_compressBound(payload.size()));
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
  const std::size_t n = ZSTD_compress2(cctx, out.data() + header, out.size() - header, payload.data(), payload.size());
  ZSTD_freeCCtx(cctx);
  if (ZSTD_isError(n)) throw Error(ErrorCode::kInternal, std::string("zstd: ") + ZSTD_getErrorName(n));
  out.resize(header + n);
  return out;
}

DecodedBlob DecodeBlob(std::string_view blob) {
  if (blob.size() < 8 || std::memcmp(blob.data(), kMagic, 4) != 0) Corrupt("bad magic");
  std::size_t pos = 4;
  const auto version = Get<std::uint16_t>(blob, pos);
  if (version != kFormatVersion) Corrupt("unknown format version " + std::to_string(version));
  DecodedBlob out;
  const auto element = Get<std::uint8_t>(blob, pos);
  if (element < 1 || element > 7) Corrupt("unknown element type " + std::to_string(element));
  out.element = static_cast<BlobElement>(element);
  const auto ndims = Get<std::uint8_t>(blob, pos);
  if (ndims < 1 || ndims > 4) Corrupt("bad number of dimensions");
  const auto filter = Get<std::uint8_t>(blob, pos);
  if (filter > 1) Corrupt("unknown filter " + std::to_string(filter));
  pos += 3;  // reserved
  std::uint64_t expected = ElementSize(out.element);
  for (int i = 0; i < ndims; ++i) {
    out.shape.push_back(Get<std::uint32_t>(blob, pos));
    expected *= out.shape.back();
    if (expected > (std::uint64_t{1} << 34)) Corrupt("shape is implausibly large");
  }
  const auto size = Get<std::uint64_t>(blob, pos);
  if (size != expected) Corrupt("payload size does not match the shape");
  const void* frame = blob.data() + pos;
  const std::size_t frame_size = blob.size() - pos;
  const unsigned long long content = ZSTD_getFrameContentSize(frame, frame_size);
  if (content == ZSTD_CONTENTSIZE_ERROR || content != size) Corrupt("zstd frame size does not match the header");
  out.bytes.resize(size);
  const std::size_t n = ZSTD_decompress(out.bytes.data(), out.bytes.size(), frame, frame_size);
  if (ZSTD_isError(n) || n != size) Corrupt(std::string("zstd: ") + (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "short"));
  if (filter == static_cast<std::uint8_t>(BlobFilter::kDeltaShuffle16)) {
    if (ElementSize(out.element) != 2) Corrupt("delta-shuffle filter on a non-16-bit blob");
    UndoDeltaShuffle16(out.bytes, out.shape.back() == 0 ? 1 : out.shape.back());
  }
  return out;
}

}  // namespace anchordb::storage
