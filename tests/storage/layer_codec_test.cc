// The record format of grid layers (storage/layer_codec.h): every kind round-trips through a LayerRecord, and records
// whose kind, metadata and blob do not agree are kInternal naming the layer.
#include "storage/layer_codec.h"

#include <gtest/gtest.h>

#include <functional>

#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::storage {
namespace layer_codec_test {

GridGeometry Geometry() {
  GridGeometry g;
  g.width_cells = 3;
  g.height_cells = 2;
  g.resolution_m = 0.05;
  g.origin_x_m = -1.25;
  g.origin_y_m = 2.5;
  g.origin_yaw_rad = 0.125;
  return g;
}

LayerRecord Named(const std::string& name) {
  LayerRecord r;
  r.map_id = "m";
  r.name = name;
  return r;
}

// Encodes `layer`, decodes it with `decode` and encodes that again: the row must be byte-identical.
template <typename Layer, typename Decode>
Layer RoundTrip(const Layer& layer, LayerKind kind, Decode decode) {
  LayerRecord first = Named("l");
  EncodeLayer(layer, first);
  EXPECT_EQ(first.kind, kind);
  const Layer back = decode(first);
  LayerRecord second = Named("l");
  EncodeLayer(back, second);
  EXPECT_EQ(second.meta.index(), static_cast<std::size_t>(kind));
  EXPECT_EQ(second.data, first.data);
  EXPECT_EQ(DecodeGeometry(first), Geometry());
  return back;
}

TEST(LayerCodecTest, OccupancyRoundTrips) {
  OccupancyLayer layer;
  layer.meta.geometry = Geometry();
  layer.meta.map_server.image = "map.pgm";
  layer.meta.map_server.resolution_m = 0.05;
  layer.meta.map_server.origin[0] = -1.25;
  layer.meta.map_server.negate = 1;
  layer.meta.map_server.mode = MapMode::kRaw;
  layer.meta.map_server.mode_given = true;
  layer.meta.ignored_yaml_keys = {"comment", "x"};
  layer.image_pixels = {0, 254, 205, 1, 2, 3};
  const OccupancyLayer back = RoundTrip(layer, LayerKind::kOccupancy, DecodeOccupancyLayer);
  EXPECT_EQ(back.image_pixels, layer.image_pixels);
  EXPECT_EQ(back.meta.map_server.image, "map.pgm");
  EXPECT_EQ(back.meta.map_server.negate, 1);
  EXPECT_EQ(back.meta.map_server.mode, MapMode::kRaw);
  EXPECT_TRUE(back.meta.map_server.mode_given);
  EXPECT_EQ(back.meta.ignored_yaml_keys, layer.meta.ignored_yaml_keys);
}

TEST(LayerCodecTest, ProbabilityRoundTrips) {
  ProbabilityLayer layer{{Geometry(), "occ", {0.8, 0.3, 0.1, 0.99}, 7}, {0.f, 1.5f, -2.f, 3.f, 0.25f, -0.5f}};
  const ProbabilityLayer back = RoundTrip(layer, LayerKind::kProbability, DecodeProbabilityLayer);
  EXPECT_EQ(back.log_odds, layer.log_odds);
  EXPECT_EQ(back.meta.base, "occ");
  EXPECT_EQ(back.meta.log_odds.hit_probability, 0.8);
  EXPECT_EQ(back.meta.log_odds.clamp_max_probability, 0.99);
  EXPECT_EQ(back.meta.observations, 7);
}

TEST(LayerCodecTest, FusedRoundTrips) {
  const FusedLayerMeta meta{Geometry(), FuseOp::kAndNot, {{"a", 0.25}, {"b", 0.5}}};
  const FusedLayerMeta back = RoundTrip(meta, LayerKind::kFused, DecodeFusedMeta);
  EXPECT_EQ(back.op, FuseOp::kAndNot);
  ASSERT_EQ(back.operands.size(), 2u);
  EXPECT_EQ(back.operands[0].layer, "a");
  EXPECT_EQ(back.operands[0].threshold, 0.25);
}

TEST(LayerCodecTest, LabelRoundTrips) {
  LabelLayer layer{{Geometry(), "occ", {{1, "hall"}, {10, "kitchen"}, {65535, "last"}}}, {0, 1, 10, 65535, 0, 1}};
  const LabelLayer back = RoundTrip(layer, LayerKind::kLabel, DecodeLabelLayer);
  EXPECT_EQ(back.label_ids, layer.label_ids);
  EXPECT_EQ(back.meta.labels, layer.meta.labels);
}

TEST(LayerCodecTest, TheCellsAreAnArrayInTheBlobEnvelope) {
  LayerRecord r = Named("p");
  EncodeLayer(ProbabilityLayer{{Geometry(), "occ", {}, 2}, std::vector<float>(6, 0.f)}, r);
  const DecodedBlob blob = DecodeBlob(r.data);
  EXPECT_EQ(blob.element, BlobElement::kF32);
  EXPECT_EQ(blob.shape, (std::vector<std::uint32_t>{2, 3}));
}

void ExpectInternal(const std::function<void()>& f, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "expected kInternal: " << what;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal) << what;
    EXPECT_NE(std::string(e.what()).find("'bad'"), std::string::npos) << what << ": " << e.what();
  }
}

TEST(LayerCodecTest, RowsNotMatchingTheFormatAreInternalErrors) {
  LayerRecord good = Named("bad");
  EncodeLayer(LabelLayer{{Geometry(), "occ", {{1, "hall"}}}, std::vector<std::uint16_t>(6, 0)}, good);

  LayerRecord r = good;
  r.meta = ProbabilityLayerMeta{Geometry(), "occ", {}, 0};
  ExpectInternal([&] { DecodeLabelMeta(r); }, "metadata of another kind");
  ExpectInternal([&] { DecodeGeometry(r); }, "metadata of another kind (geometry)");
  r = good;
  std::get<LabelLayerMeta>(r.meta).geometry.width_cells = -3;
  ExpectInternal([&] { DecodeGeometry(r); }, "negative size");
  r = good;
  std::get<LabelLayerMeta>(r.meta).geometry.resolution_m = 0;
  ExpectInternal([&] { DecodeLabelMeta(r); }, "zero resolution");
  r = good;
  std::get<LabelLayerMeta>(r.meta).labels[70000] = "x";
  ExpectInternal([&] { DecodeLabelMeta(r); }, "label id out of range");
  r = good;
  r.kind = LayerKind::kProbability;
  ExpectInternal([&] { DecodeLabelMeta(r); }, "wrong kind");
  r = good;
  r.data = EncodeBlob(BlobElement::kU16, {3, 2}, AsBytes(std::vector<std::uint16_t>(6, 0)));
  ExpectInternal([&] { DecodeLabelLayer(r); }, "transposed shape");
  r.data = EncodeBlob(BlobElement::kU8, {2, 3}, AsBytes(std::vector<std::uint8_t>(6, 0)));
  ExpectInternal([&] { DecodeLabelLayer(r); }, "wrong element");
  LayerRecord fused = Named("bad");
  EncodeLayer(FusedLayerMeta{Geometry(), FuseOp::kOr, {{"a", 0.5}, {"b", 0.5}}}, fused);
  std::get<FusedLayerMeta>(fused.meta).operands.clear();
  ExpectInternal([&] { DecodeFusedMeta(fused); }, "no operands");
}

}  // namespace
}  // namespace anchordb::storage
