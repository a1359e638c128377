// Writes the seeds of anchordb_fuzz_decoders into a directory: valid inputs of every decoder, made with the
// project's own encoders (the stored-codec seeds decoded back before they are written). The first byte selects the
// decoder (decoders_fuzz.cc); a layer record's own selector picks the layer decoder (stored_codecs.h). The seeds are
// committed in tests/fuzz/corpus/decoders; rerun this (same names, same bytes) when an encoder's format changes:
//   build-fuzz/anchordb_fuzz_seeds tests/fuzz/corpus/decoders
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include "engine/cloud/cloud_io.h"
#include "engine/grid/map_server.h"
#include "engine/octomap/occupancy_tree.h"
#include "engine/scene/depth_image.h"
#include "storage/blob_codec.h"
#include "schema/json_io.h"
#include "storage/feature_documents.h"
#include "storage/job_documents.h"
#include "storage/segmentation_documents.h"
#include "storage/classifier_documents.h"
#include "storage/shape_documents.h"
#include "tests/fuzz/stored_codecs.h"

using namespace anchordb;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  int n = 0;
  const auto put = [&](std::uint8_t which, const std::string& name, const std::string& body) {
    std::ofstream(dir / ("seed-" + name), std::ios::binary) << static_cast<char>(which) << body;
    ++n;
  };
  // A seed the decoder refuses would only test the refusal: each layer seed is decoded back here first, with the
  // decoder its selector names (stored_codecs.h), and must give what was encoded: the same kind, geometry and, for
  // the whole-record decoders, the same blob bytes when encoded again.
  const auto layer_seed = [](std::uint8_t selector, const storage::LayerRecord& encoded, bool with_blob) {
    const GridGeometry geometry = fuzz::layer_codec::DecodeGeometry(encoded);
    const std::string input = fuzz::JoinLayerInput(selector, geometry, encoded.meta.index(), with_blob ? encoded.data : "");
    const fuzz::LayerInput in = fuzz::SplitLayerInput(input);
    const storage::LayerRecord record = in.Record();
    namespace lc = fuzz::layer_codec;
    using D = fuzz::LayerDecoder;
    storage::LayerRecord again = record;
    switch (in.decoder()) {
      case D::kOccupancyLayer: lc::EncodeLayer(lc::DecodeOccupancyLayer(record), again); break;
      case D::kProbabilityLayer: lc::EncodeLayer(lc::DecodeProbabilityLayer(record), again); break;
      case D::kLabelLayer: lc::EncodeLayer(lc::DecodeLabelLayer(record), again); break;
      case D::kFusedMeta: lc::EncodeLayer(lc::DecodeFusedMeta(record), again); break;
      case D::kOccupancyMeta: (void)lc::DecodeOccupancyMeta(record); break;
      case D::kProbabilityMeta: (void)lc::DecodeProbabilityMeta(record); break;
      case D::kLabelMeta: (void)lc::DecodeLabelMeta(record); break;
      case D::kGeometry: (void)lc::DecodeGeometry(record); break;
    }
    const GridGeometry g = lc::DecodeGeometry(again);
    if (record.kind != encoded.kind || again.kind != record.kind || g.width_cells != geometry.width_cells ||
        g.height_cells != geometry.height_cells || again.data != record.data) {
      throw std::logic_error("a layer seed does not decode to what was encoded");
    }
    return input;
  };
  std::vector<std::uint16_t> depth(8 * 6);
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = static_cast<std::uint16_t>(1000 + 37 * i);
  put(0, "blob-u16-delta", storage::EncodeBlob(storage::BlobElement::kU16, {6, 8}, storage::AsBytes(depth), 3,
                                               storage::BlobFilter::kDeltaShuffle16));
  std::vector<float> metres(8 * 6, 1.5f);
  put(0, "blob-f32", storage::EncodeBlob(storage::BlobElement::kF32, {6, 8}, storage::AsBytes(metres)));
  put(1, "depth-png", engine::EncodeDepthPng(depth, 8, 6));
  std::vector<std::uint8_t> mask(8 * 6, 0);
  mask[7] = mask[20] = 1;
  put(2, "mask-png", engine::EncodeMaskPng(mask, 8, 6));
  put(3, "depth-raw", std::string(reinterpret_cast<const char*>(depth.data()), depth.size() * 2));
  MapServerMeta meta;
  meta.image = "map.pgm";
  put(4, "map-yaml", engine::EmitMapServerYaml(meta));
  engine::GreyImage grey{8, 6, std::vector<std::uint8_t>(48, 254)};
  grey.pixels[9] = 0;
  put(5, "map-pgm", engine::EncodePgm(grey));
  put(5, "map-png", engine::EncodePng(grey));
  put(6, "json-pose", R"({"pose":{"position":[1,2,0],"orientation":[0,0,0.7071068,0.7071068]},"stimulus":[[[0,0],[1,0],[1,1]]],)"
                      R"("stamp":"2026-11-23T05:30:07.250Z"})");
  put(6, "json-params", R"({"params":{"hit":0.7,"miss":0.4,"clamp_min":0.12,"clamp_max":0.97},"stamp":1795411807000000000})");
  put(7, "iso8601", "2026-11-23T05:30:07+01:00");

  // Furniture-graph hypotheses: the graph as seen, and after one description.
  namespace g = engine::grounding;
  const g::FurnitureGraph& graph = fuzz::FuzzGraph();
  const g::HypothesisSet initial = g::InitialHypotheses(graph);
  g::GroundingParams params;
  params.n_best = 6;
  const g::Description said{0, g::Relation::kLeftOf, 1};
  const g::HypothesisSet grounded = g::Ground(graph, g::DefaultKnowledge(), initial, said, params);
  for (const auto& [name, set] : {std::pair{"hypotheses-initial", &initial}, std::pair{"hypotheses-grounded", &grounded}}) {
    const std::string blob = fuzz::hypotheses_codec::EncodeHypotheses(graph, *set);
    if (fuzz::hypotheses_codec::DecodeHypotheses(graph, blob).ranked.size() != set->ranked.size()) {
      throw std::logic_error("a hypotheses seed does not decode to what was encoded");
    }
    put(8, name, blob);
  }

  // Layer records as the grid service stores them (storage/layer_codec.h: meta JSON + blob per kind), whole, and
  // the metadata alone as read without the blob.
  namespace lc = fuzz::layer_codec;
  using D = fuzz::LayerDecoder;
  const auto selector = [](D decoder, LayerKind kind = LayerKind::kOccupancy) {
    return static_cast<std::uint8_t>(static_cast<int>(decoder) + 8 * static_cast<int>(kind));
  };
  GridGeometry geometry;
  geometry.width_cells = 8;
  geometry.height_cells = 6;
  geometry.resolution_m = 0.1;
  geometry.origin_x_m = -0.4;
  geometry.origin_y_m = -0.3;
  storage::LayerRecord record;
  lc::OccupancyLayer occupancy;
  occupancy.meta.geometry = geometry;
  occupancy.meta.map_server = meta;
  occupancy.meta.ignored_yaml_keys = {"frame_id"};
  occupancy.image_pixels = grey.pixels;
  lc::EncodeLayer(occupancy, record);
  put(9, "layer-occupancy", layer_seed(selector(D::kOccupancyLayer), record, true));
  put(9, "layer-occupancy-meta", layer_seed(selector(D::kOccupancyMeta), record, false));
  lc::ProbabilityLayer probability;
  probability.meta.geometry = geometry;
  probability.meta.base = "floor";
  probability.meta.log_odds.hit_probability = 0.7;
  probability.meta.log_odds.miss_probability = 0.4;
  probability.meta.log_odds.clamp_min_probability = 0.12;
  probability.meta.log_odds.clamp_max_probability = 0.97;
  probability.meta.observations = 2;
  probability.log_odds.assign(48, 0.0f);
  probability.log_odds[5] = 0.85f;
  probability.log_odds[30] = -0.4f;
  lc::EncodeLayer(probability, record);
  put(9, "layer-probability", layer_seed(selector(D::kProbabilityLayer), record, true));
  put(9, "layer-probability-meta", layer_seed(selector(D::kProbabilityMeta), record, false));
  lc::LabelLayer label;
  label.meta.geometry = geometry;
  label.meta.base = "floor";
  label.meta.labels = {{1, "kitchen"}, {2, "hall"}};
  label.label_ids.assign(48, 0);
  label.label_ids[10] = label.label_ids[11] = 1;
  label.label_ids[40] = 2;
  lc::EncodeLayer(label, record);
  put(9, "layer-label", layer_seed(selector(D::kLabelLayer), record, true));
  put(9, "layer-label-meta", layer_seed(selector(D::kLabelMeta), record, false));
  lc::FusedLayerMeta fused;
  fused.geometry = geometry;
  fused.op = FuseOp::kAndNot;
  fused.operands = {{"floor", 0.5}};
  lc::EncodeLayer(fused, record);
  put(9, "layer-fused-meta", layer_seed(selector(D::kFusedMeta), record, false));
  put(9, "layer-fused-geometry", layer_seed(selector(D::kGeometry, LayerKind::kFused), record, false));
  // OctoMap trees (.bt, .ot) and point clouds (PCD in every DATA kind, PLY) of a small wall (issue 14).
  std::vector<Eigen::Vector3f> wall;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) wall.emplace_back(1.0f, 0.05f * i, 0.05f * j);
  }
  engine::OccupancyTree tree(engine::OccupancyTreeParams{0.1});
  tree.InsertCloud(wall, Eigen::Vector3d(0, 0, 0.1), 3.0, 1);
  put(10, "octomap-bt", tree.WriteBt());
  put(11, "octomap-ot", tree.WriteOt());
  put(12, "cloud-pcd-ascii", engine::EncodeCloud(wall, engine::CloudFormat::kPcdAscii));
  put(12, "cloud-pcd-binary", engine::EncodeCloud(wall, engine::CloudFormat::kPcdBinary));
  put(12, "cloud-pcd-binary-compressed", engine::EncodeCloud(wall, engine::CloudFormat::kPcdBinaryCompressed));
  put(12, "cloud-ply-ascii", engine::EncodeCloud(wall, engine::CloudFormat::kPlyAscii));
  put(12, "cloud-ply-binary", engine::EncodeCloud(wall, engine::CloudFormat::kPlyBinary));
  // Typed stored documents (issue 30): the byte after the selector picks the decoder (decoders_fuzz.cc).
  storage::ForgetRequest forget;
  forget.now_ns = 1'700'000'000'000'000'000;
  storage::ForgetReport forgotten;
  forgotten.map_id = "home";
  forgotten.keyframes_deleted = {3, 4};
  forgotten.vacuum_mode = "incremental";
  storage::SegmentationJobRequest segment;
  segment.source = "keyframes";
  segment.keyframes = {1, 2};
  segment.shape_model = "chairs";
  segment.params = {{"voxel_m", 0.02}, {"min_cluster_points", 150}};
  storage::SegmentationJobResult segmented;
  segmented.map_id = "home";
  segmented.planes = {"floor"};
  segmented.floor_z_m = 0.0;
  segmented.segments = {{"created", 7, "table", 0.8, "geometry", 1.0, 2.0, 1.2, 0.8, 0.1, 0.74, 900}};
  const auto document = [](char decoder, const std::string& encoded) { return std::string(1, decoder) + encoded; };
  put(13, "document-forget-request", document(0, storage::EncodeForgetRequest(forget)));
  put(13, "document-forget-report", document(1, storage::EncodeForgetReport(forgotten)));
  put(13, "document-backup-request", document(2, storage::EncodeBackupRequest({"/b/home.sqlite"})));
  put(13, "document-backup-report", document(3, storage::EncodeBackupReport({"/b/home.sqlite", 4096, 1, 0, "ok", 0.5})));
  put(13, "document-codebook-request", document(4, storage::EncodeCodebookRequest({"fpfh", 64, 1})));
  put(13, "document-codebook-result", document(5, storage::EncodeCodebookResult({"fpfh", 64, 33, 500, 500})));
  put(13, "document-segmentation-request", document(6, storage::EncodeSegmentationRequest(segment)));
  put(13, "document-segmentation-result", document(7, storage::EncodeSegmentationResult(segmented)));
  storage::ClassifierOptionsRecord options;
  options.name = "rooms";
  options.base = {{"svm", 1.0, 0.5, true, 0, 0, {}, 0, 0}, {"mlp", 0, 0, false, 0, 0, {16, 8}, 200, 0}};
  options.selection = "maximum";
  storage::ClassifierReportRecord report;
  report.classes = {"kitchen", "hall"};
  report.rounds = {{"knn(k=3)", "bow", 0.1, 1.2}};
  report.cross_validation = storage::ClassifierCrossValidationRecord{};
  report.cross_validation->confusion = {{3, 1}, {0, 4}};
  report.cross_validation->kind_share = {{"knn", 1.0}};
  storage::ShapeModelOptionsRecord shape;
  shape.name = "chairs";
  shape.params.codebook_size = 60;
  shape.parts = {{"chair.obj", "chair", true, 812}, {"scan.pcd", "chair", false, 4000}};
  storage::ShapeModelReportRecord shape_report;
  shape_report.categories = {{"chair", 13, 480}};
  put(13, "document-classifier-options", document(8, storage::EncodeClassifierOptions(options)));
  put(13, "document-classifier-report", document(9, storage::EncodeClassifierReport(report)));
  put(13, "document-classifier-request", document(10, storage::EncodeClassifierTrainingRequest({options, 60, {{"hall", 30}}, {{"bow", 64}}, 1})));
  put(13, "document-classifier-result", document(11, storage::EncodeClassifierTrainingResult({"rooms", 10, 0.5, 0.1})));
  put(13, "document-shape-options", document(12, storage::EncodeShapeModelOptions(shape)));
  put(13, "document-shape-report", document(13, storage::EncodeShapeModelReport(shape_report)));
  put(13, "document-shape-request", document(14, storage::EncodeShapeTrainingRequest({shape, 2})));
  put(13, "document-shape-result", document(15, storage::EncodeShapeTrainingResult({"chairs", 13, 480, 2.5})));
  std::printf("%d seeds in %s\n", n, dir.c_str());
  return 0;
}
