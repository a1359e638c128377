#include "storage/blob_codec.h"

#include <gtest/gtest.h>

#include <random>

#include "schema/error.h"

namespace anchordb::storage {
namespace blob_codec_test {

TEST(BlobCodecTest, RoundTripEveryElementType) {
  std::mt19937 rng(7);
  for (BlobElement e : {BlobElement::kU8, BlobElement::kI8, BlobElement::kU16, BlobElement::kI16, BlobElement::kF32,
                        BlobElement::kF64, BlobElement::kU32}) {
    const std::vector<std::uint32_t> shape = {17, 23};
    std::string payload(ElementSize(e) * 17 * 23, '\0');
    for (char& c : payload) c = static_cast<char>(rng() % 7);  // compressible but not constant
    const std::string blob = EncodeBlob(e, shape, payload);
    EXPECT_LT(blob.size(), payload.size());
    const DecodedBlob d = DecodeBlob(blob);
    EXPECT_EQ(d.element, e);
    EXPECT_EQ(d.shape, shape);
    EXPECT_EQ(d.bytes, payload);
  }
}

TEST(BlobCodecTest, HeaderLayoutIsTheDocumentedOne) {
  const std::vector<float> v(6, 1.5f);
  const std::string blob = EncodeBlob(BlobElement::kF32, {2, 3}, AsBytes(v));
  EXPECT_EQ(blob.substr(0, 4), "ADBB");
  EXPECT_EQ(static_cast<unsigned char>(blob[4]), 1);  // version, little-endian
  EXPECT_EQ(static_cast<unsigned char>(blob[6]), static_cast<unsigned char>(BlobElement::kF32));
  EXPECT_EQ(static_cast<unsigned char>(blob[7]), 2);  // dimensions
  EXPECT_EQ(static_cast<unsigned char>(blob[8]), 0);  // no filter
  EXPECT_EQ(static_cast<unsigned char>(blob[12]), 2);
  EXPECT_EQ(static_cast<unsigned char>(blob[16]), 3);
}

TEST(BlobCodecTest, CorruptionIsDetectedNotMisread) {
  const std::vector<float> v(100, 2.0f);
  const std::string good = EncodeBlob(BlobElement::kF32, {10, 10}, AsBytes(v));
  std::string bad_magic = good;
  bad_magic[0] = 'X';
  EXPECT_THROW(DecodeBlob(bad_magic), Error);
  std::string bad_shape = good;
  bad_shape[12] = 11;
  EXPECT_THROW(DecodeBlob(bad_shape), Error);
  std::string flipped = good;
  flipped[flipped.size() - 6] ^= 0x5a;  // inside the zstd frame: the content checksum catches it
  EXPECT_THROW(DecodeBlob(flipped), Error);
  EXPECT_THROW(DecodeBlob(good.substr(0, good.size() - 3)), Error);
  EXPECT_THROW(DecodeBlob(""), Error);
}

TEST(BlobCodecTest, DeltaShuffleFilterRoundTripsAndShrinksSmoothDepth) {
  // A smooth 16-bit depth image (a tilted plane with mm noise) with holes of zero.
  std::mt19937 rng(3);
  const int w = 640, h = 480;
  std::vector<std::uint16_t> depth(w * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      depth[y * w + x] = (x * 7 + y * 3) % 97 == 0 ? 0 : static_cast<std::uint16_t>(1200 + y * 4 + x / 3 + rng() % 5);
    }
  }
  const std::string plain = EncodeBlob(BlobElement::kU16, {480, 640}, AsBytes(depth), 3);
  const std::string filtered = EncodeBlob(BlobElement::kU16, {480, 640}, AsBytes(depth), 3, BlobFilter::kDeltaShuffle16);
  EXPECT_LT(filtered.size(), plain.size());
  EXPECT_EQ(static_cast<unsigned char>(filtered[8]), 1);
  EXPECT_EQ(DecodeBlob(filtered).bytes, std::string(AsBytes(depth)));
  EXPECT_THROW(EncodeBlob(BlobElement::kF32, {1}, std::string(4, 'x'), 3, BlobFilter::kDeltaShuffle16), Error);
}

TEST(BlobCodecTest, EncodeChecksShape) {
  EXPECT_THROW(EncodeBlob(BlobElement::kU16, {3}, "abc"), Error);
  EXPECT_THROW(EncodeBlob(BlobElement::kU8, {}, ""), Error);
}

}  // namespace
}  // namespace anchordb::storage
