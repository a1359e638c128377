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

std::string EncodeBlob(BlobElement element, const std::vector<std::uint32_t>& shape, std::string_view payload, int level) {
  if (shape.empty() || shape.size() > 4) throw Error(ErrorCode::kInternal, "blob shape must have 1-4 dimensions");
  std::uint64_t expected = ElementSize(element);
  for (auto d : shape) expected *= d;
  if (expected != payload.size()) throw Error(ErrorCode::kInternal, "blob payload size does not match its shape");
  std::string out(kMagic, 4);
  Put<std::uint16_t>(out, kFormatVersion);
  Put<std::uint8_t>(out, static_cast<std::uint8_t>(element));
  Put<std::uint8_t>(out, static_cast<std::uint8_t>(shape.size()));
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
  return out;
}

}  // namespace anchordb::storage
