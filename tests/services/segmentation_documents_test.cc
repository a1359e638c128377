// A segmentation job's stored request (services/segmentation/segmentation_request.cc over
// storage/segmentation_documents.h): every option and parameter comes back as submitted, a parameter this build does
// not know is ignored and one the document lacks keeps its default; the result keeps every segment.
#include <gtest/gtest.h>

#include "services/segmentation/furniture_segmentation_service.h"
#include "storage/segmentation_documents.h"

namespace anchordb::services {
namespace segmentation_documents_test {

TEST(SegmentationDocumentsTest, ARequestComesBackAsSubmitted) {
  SegmentationRequest r;
  r.source = SegmentationSource::kCloud;
  r.max_keyframes = 17;
  r.max_range_m = 2.75;
  r.shape_model = "chairs";
  r.use_stored_shape_model = false;
  r.match_iou = 0.45;
  r.params.voxel_m = 0.035;
  r.params.plane_iterations = 123;
  r.params.min_plane_points = 777;
  r.params.min_cluster_points = 321;
  r.params.outlier_min_neighbours = 6;
  r.params.core_density = 0.625;
  std::optional<std::int64_t> staging;
  const SegmentationRequest back = SegmentationRequestFromDocument(SegmentationRequestDocument(r, 42), &staging);
  EXPECT_EQ(staging, std::optional<std::int64_t>(42));
  EXPECT_EQ(back.source, SegmentationSource::kCloud);
  EXPECT_EQ(back.max_keyframes, 17);
  EXPECT_EQ(back.max_range_m, 2.75);
  EXPECT_EQ(back.shape_model, std::optional<std::string>("chairs"));
  EXPECT_FALSE(back.use_stored_shape_model);
  EXPECT_EQ(back.match_iou, 0.45);
  EXPECT_EQ(back.params.voxel_m, 0.035);
  EXPECT_EQ(back.params.plane_iterations, 123);
  EXPECT_EQ(back.params.min_plane_points, 777u);
  EXPECT_EQ(back.params.min_cluster_points, 321u);
  EXPECT_EQ(back.params.outlier_min_neighbours, 6);
  EXPECT_EQ(back.params.core_density, 0.625);

  SegmentationRequest keyframes;
  keyframes.keyframes = {4, 9};
  const SegmentationRequest k = SegmentationRequestFromDocument(SegmentationRequestDocument(keyframes), &staging);
  EXPECT_EQ(k.keyframes, (std::vector<std::int64_t>{4, 9}));
  EXPECT_FALSE(staging.has_value());
  EXPECT_FALSE(k.shape_model.has_value());
}

TEST(SegmentationDocumentsTest, UnknownParametersAreIgnoredAndMissingOnesKeepTheirDefaults) {
  storage::SegmentationJobRequest stored;
  stored.source = "octomap";
  stored.max_keyframes = 5;
  stored.params = {{"a_parameter_of_a_later_release", 9.0}, {"band_m", 0.12}};
  const SegmentationRequest r = SegmentationRequestFromDocument(storage::EncodeSegmentationRequest(stored), nullptr);
  const engine::segmentation::SegmentationParams defaults;
  EXPECT_EQ(r.source, SegmentationSource::kOctomap);
  EXPECT_EQ(r.params.band_m, 0.12);
  EXPECT_EQ(r.params.voxel_m, defaults.voxel_m);
  EXPECT_EQ(r.params.min_cluster_points, defaults.min_cluster_points);
}

TEST(SegmentationDocumentsTest, AResultKeepsEverySegment) {
  SegmentationOutcome out;
  out.source = "keyframes";
  out.input_points = 5000;
  out.planes = {"floor", "wall"};
  out.floor_z_m = -0.01;
  SegmentOutcome created;
  created.action = "created";
  created.instance.id = 31;
  created.instance.label = "table";
  created.instance.position_m = {1.5, -2.0};
  created.instance.extent_m = {1.2, 0.8};
  created.instance.points = 900;
  SegmentOutcome kept = created;
  kept.action = "kept_operator";
  kept.instance.id = 8;
  out.segments = {created, kept};
  const storage::SegmentationJobResult r =
      storage::DecodeSegmentationResult(SegmentationResultDocument(out, "home"), "job 3");
  EXPECT_EQ(r.map_id, "home");
  EXPECT_EQ(r.input_points, 5000);
  EXPECT_EQ(r.planes, out.planes);
  EXPECT_EQ(r.floor_z_m, std::optional<double>(-0.01));
  EXPECT_FALSE(r.shape_model.has_value());
  ASSERT_EQ(r.segments.size(), 2u);
  EXPECT_EQ(r.segments[0].furniture, 31);
  EXPECT_EQ(r.segments[0].label, "table");
  EXPECT_EQ(r.segments[0].x_m, 1.5);
  EXPECT_EQ(r.segments[0].extent_y_m, 0.8);
  EXPECT_EQ(r.segments[0].points, 900);
  EXPECT_EQ(r.segments[1].action, "kept_operator");
  EXPECT_EQ(r.segments[1].furniture, 8);
}

}  // namespace
}  // namespace anchordb::services
