#include "engine/image/png_codec.h"

#include <spng.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace anchordb::engine {
namespace {

struct CtxFree {
  void operator()(spng_ctx* c) const { spng_ctx_free(c); }
};
using Ctx = std::unique_ptr<spng_ctx, CtxFree>;

bool Fail(std::string* why, const char* what, int code = 0) {
  if (why) *why = code ? std::string(what) + ": " + spng_strerror(code) : std::string(what);
  return false;
}

}  // namespace

std::optional<std::pair<std::uint32_t, std::uint32_t>> PngHeaderSize(std::string_view png) {
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // The signature, then the IHDR chunk: length (4), "IHDR", width (4, big-endian), height (4).
  if (png.size() < 24 || std::memcmp(png.data(), kSignature, 8) != 0 || png.substr(12, 4) != "IHDR") return std::nullopt;
  const auto be32 = [&](std::size_t o) {
    return (std::uint32_t(std::uint8_t(png[o])) << 24) | (std::uint32_t(std::uint8_t(png[o + 1])) << 16) |
           (std::uint32_t(std::uint8_t(png[o + 2])) << 8) | std::uint32_t(std::uint8_t(png[o + 3]));
  };
  return std::pair<std::uint32_t, std::uint32_t>(be32(16), be32(20));
}

std::optional<PngImage> DecodePngImage(std::string_view png, std::string* why) {
  Ctx ctx(spng_ctx_new(0));
  if (!ctx) return Fail(why, "out of memory"), std::nullopt;
  // Ancillary chunks are bounded too (text, ICC profiles): a body cannot make the decoder cache more than 16 MB.
  spng_set_chunk_limits(ctx.get(), 16u << 20, 16u << 20);
  if (int e = spng_set_png_buffer(ctx.get(), png.data(), png.size())) return Fail(why, "not a PNG", e), std::nullopt;
  spng_ihdr ihdr{};
  if (int e = spng_get_ihdr(ctx.get(), &ihdr)) return Fail(why, "bad PNG header", e), std::nullopt;
  PngImage out;
  out.width = static_cast<int>(ihdr.width);
  out.height = static_cast<int>(ihdr.height);
  int format = SPNG_FMT_PNG;  // the file's own layout, 16-bit host-endian
  int flags = 0;
  const bool sixteen = ihdr.bit_depth == 16;
  switch (ihdr.color_type) {
    case SPNG_COLOR_TYPE_GRAYSCALE:
      out.channels = 1;
      if (ihdr.bit_depth < 8) format = SPNG_FMT_G8;
      break;
    case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA: out.channels = 2; break;
    case SPNG_COLOR_TYPE_TRUECOLOR: out.channels = 3; break;
    case SPNG_COLOR_TYPE_TRUECOLOR_ALPHA: out.channels = 4; break;
    case SPNG_COLOR_TYPE_INDEXED:
      out.channels = 4;
      format = SPNG_FMT_RGBA8;
      flags = SPNG_DECODE_TRNS;
      break;
    default: return Fail(why, "unknown PNG colour type"), std::nullopt;
  }
  out.bit_depth = sixteen && format == SPNG_FMT_PNG ? 16 : 8;
  std::size_t size = 0;
  if (int e = spng_decoded_image_size(ctx.get(), format, &size)) return Fail(why, "bad PNG", e), std::nullopt;
  if (size != out.row_bytes() * static_cast<std::size_t>(out.height)) return Fail(why, "unexpected PNG layout"), std::nullopt;
  // Deflate expands at most ~1032:1, so a file can only hold so many pixels: a few hundred bytes declaring megapixels
  // are refused before width x height bytes are allocated and zeroed.
  if (size / 1032 > png.size() + 1024) return Fail(why, "declares more pixels than its data can hold"), std::nullopt;
  out.bytes.resize(size);
  if (int e = spng_decode_image(ctx.get(), out.bytes.data(), size, format, flags)) {
    return Fail(why, "the PNG could not be decoded", e), std::nullopt;
  }
  // The rest of the file up to IEND, CRCs checked: a truncated or damaged file is refused even when its pixels came
  // through whole.
  if (int e = spng_decode_chunks(ctx.get())) return Fail(why, "damaged after the image data", e), std::nullopt;
  static constexpr char kIend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', '\xae', '\x42', '\x60', '\x82'};  // length 0, CRC
  if (png.find(std::string_view(kIend, 12)) == std::string_view::npos) return Fail(why, "no end chunk (IEND)"), std::nullopt;
  return out;
}

std::string EncodePngImage(const PngImage& image, int compression_level) {
  static constexpr std::uint8_t kColourType[5] = {0, SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA,
                                                  SPNG_COLOR_TYPE_TRUECOLOR, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
  if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4 ||
      (image.bit_depth != 8 && image.bit_depth != 16) ||
      image.bytes.size() != image.row_bytes() * static_cast<std::size_t>(image.height)) {
    throw std::invalid_argument("EncodePngImage: the image's size, channels or bit depth do not fit its bytes");
  }
  Ctx ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) throw std::bad_alloc();
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, compression_level);
  spng_ihdr ihdr{};
  ihdr.width = static_cast<std::uint32_t>(image.width);
  ihdr.height = static_cast<std::uint32_t>(image.height);
  ihdr.bit_depth = static_cast<std::uint8_t>(image.bit_depth);
  ihdr.color_type = kColourType[image.channels];
  if (int e = spng_set_ihdr(ctx.get(), &ihdr)) throw std::runtime_error(std::string("PNG header: ") + spng_strerror(e));
  if (int e = spng_encode_image(ctx.get(), image.bytes.data(), image.bytes.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE)) {
    throw std::runtime_error(std::string("PNG encoding: ") + spng_strerror(e));
  }
  std::size_t length = 0;
  int error = 0;
  void* buffer = spng_get_png_buffer(ctx.get(), &length, &error);
  if (!buffer) throw std::runtime_error(std::string("PNG encoding: ") + spng_strerror(error));
  std::string out(static_cast<const char*>(buffer), length);
  std::free(buffer);
  return out;
}

}  // namespace anchordb::engine
