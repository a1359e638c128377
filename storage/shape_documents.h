#pragma once
// The stored documents of a 3D shape model (storage/document_codec.h): its training options (with the model and, with
// the staging number, as the training job's request), its training report (with the model) and the job's result.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace anchordb::storage {

// engine::ShapeModelParams, field for field.
struct ShapeModelParamsRecord {
  double voxel_m = 0.0;
  double normal_radius_m = 0.0;
  double boundary_angle_rad = 0.0;
  double keypoint_spacing_m = 0.0;
  double shot_radius_m = 0.0;
  int codebook_size = 0;
  int activated_words = 0;
  int azimuth_bins = 0;
  int polar_bins = 0;
  double sphere_radius_m = 0.0;
  double detection_spacing_m = 0.0;
  double accept_fraction = 0.0;
  double merge_distance_m = 0.0;
  int max_keypoints = 0;
  std::uint64_t seed = 0;
  double size_weight = 0.0;
  double size_bandwidth = 0.0;
  double size_floor = 0.0;
};

// One training part as it arrived: a cloud (`count` points) or a mesh (`count` triangles).
struct ShapeTrainingPartRecord {
  std::string part;
  std::string category;
  bool mesh = false;
  std::int64_t count = 0;
};

struct ShapeModelOptionsRecord {
  std::string name;
  ShapeModelParamsRecord params;
  std::int64_t mesh_views = 0;
  std::vector<ShapeTrainingPartRecord> parts;
};

// The training job's request: the options and where its samples wait in memory until the job runs.
struct ShapeTrainingRequestRecord {
  ShapeModelOptionsRecord options;
  std::int64_t staging = 0;
};

struct ShapeCategoryReportRecord {
  std::string category;
  std::int64_t samples = 0;
  std::int64_t keypoints = 0;
};

struct ShapeModelReportRecord {
  std::vector<ShapeCategoryReportRecord> categories;
  std::int64_t samples = 0;
  std::int64_t keypoints = 0;
  int codebook_size = 0;
  std::int64_t non_empty_bins = 0;
  std::int64_t mesh_views = 0;
  double train_seconds = 0.0;
};

struct ShapeTrainingResultRecord {
  std::string name;
  std::int64_t samples = 0;
  std::int64_t keypoints = 0;
  double train_seconds = 0.0;
};

// Decoders throw Error(kInternal) naming `what` for bytes that are not such a document (document_codec.h).
std::string EncodeShapeModelOptions(const ShapeModelOptionsRecord& options);
ShapeModelOptionsRecord DecodeShapeModelOptions(std::string_view stored, const std::string& what);
std::string EncodeShapeModelReport(const ShapeModelReportRecord& report);
ShapeModelReportRecord DecodeShapeModelReport(std::string_view stored, const std::string& what);
std::string EncodeShapeTrainingRequest(const ShapeTrainingRequestRecord& request);
ShapeTrainingRequestRecord DecodeShapeTrainingRequest(std::string_view stored, const std::string& what);
std::string EncodeShapeTrainingResult(const ShapeTrainingResultRecord& result);
ShapeTrainingResultRecord DecodeShapeTrainingResult(std::string_view stored, const std::string& what);

}  // namespace anchordb::storage
