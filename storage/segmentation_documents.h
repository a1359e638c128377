#pragma once
// The documents of a furniture segmentation job (storage/document_codec.h): what it was asked and what it found.
// Plain records of storage's own; services/segmentation maps them to and from the engine's parameters.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anchordb::storage {

struct SegmentationJobRequest {
  std::string source;  // "keyframes" | "octomap" | "cloud"
  std::vector<std::int64_t> keyframes;
  std::int64_t max_keyframes = 0;
  double max_range_m = 0.0;
  std::optional<std::string> shape_model;
  bool use_stored_shape_model = true;
  double match_iou = 0.0;
  std::optional<std::int64_t> staging;  // the staged room cloud of a cloud source (held in memory, not stored)
  // The segmentation parameters by name (engine/segmentation: voxel_m, plane_iterations, ...): a name this build
  // does not know is ignored and one it misses keeps its default, so parameters may be added without a new version.
  std::vector<std::pair<std::string, double>> params;
};

struct SegmentationJobSegment {
  std::string action;  // "created" | "updated" | "kept_operator"
  std::int64_t furniture = 0;  // the instance id
  std::string label;
  double label_probability = 0.0;
  std::string classifier;
  double x_m = 0.0, y_m = 0.0;  // footprint centre, map frame
  double extent_x_m = 0.0, extent_y_m = 0.0;
  double yaw_rad = 0.0, height_m = 0.0;
  std::int64_t points = 0;
};

struct SegmentationJobResult {
  std::string map_id;
  std::string source;
  std::optional<std::string> shape_model;
  bool octomap_truncated = false;
  std::int64_t bridges_cut = 0, input_points = 0, thinned_points = 0, remaining_points = 0;
  std::vector<std::string> planes;
  std::int64_t small_clusters = 0, flying_dropped = 0;
  std::optional<double> floor_z_m;
  std::vector<SegmentationJobSegment> segments;
  double seconds = 0.0;
};

std::string EncodeSegmentationRequest(const SegmentationJobRequest& request);
SegmentationJobRequest DecodeSegmentationRequest(std::string_view stored, const std::string& what);
std::string EncodeSegmentationResult(const SegmentationJobResult& result);
SegmentationJobResult DecodeSegmentationResult(std::string_view stored, const std::string& what);

}  // namespace anchordb::storage
