#pragma once
// End-to-end evaluation of furniture segmentation (thesis 5.3.1, issue 16): rooms furnished with box-built pieces
// (sim/apartment_furnished.h) or with the furniture meshes of ../shared/data/aws_small_house/furniture_converted,
// scanned from several viewpoints and segmented; and the lost-key scenario answered relative to detected furniture.
// A segment is right when its footprint IoU with a placed piece is >= 0.5; precision = right segments / segments,
// recall = pieces with a right segment / pieces, category accuracy = right segments whose most probable category
// (engine/segmentation/geometric_categories.h) is the piece's / right segments.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/segmentation/furniture_segmentation.h"

namespace anchordb::eval {

struct SegmentationScore {
  int rooms = 0, pieces = 0, segments = 0, right_segments = 0, found_pieces = 0, category_right = 0;
  int bridges_cut = 0;  // clusters cut at a bridge of flying pixels (SegmentationResult::bridges_cut), summed
  double precision() const { return segments ? static_cast<double>(right_segments) / segments : 0.0; }
  double recall() const { return pieces ? static_cast<double>(found_pieces) / pieces : 0.0; }
  double category_accuracy() const { return right_segments ? static_cast<double>(category_right) / right_segments : 0.0; }
  std::vector<double> seconds;  // segmentation time per room cloud
  std::vector<std::size_t> cloud_points;
  std::vector<std::string> misses;  // what went wrong, for the report
};

// `rooms` box-built rooms, seeds seed0, seed0 + 1, ...
// `params`: the segmentation's (default: the engine's defaults).
SegmentationScore EvaluateBoxRooms(int rooms, std::uint64_t seed0, const engine::segmentation::SegmentationParams& params = {});
// The same room furnished with the meshes of `furniture_dir` (…/furniture_converted); nullopt when it is absent.
std::optional<SegmentationScore> EvaluateMeshRooms(int rooms, std::uint64_t seed0, const std::string& furniture_dir,
                                                   const engine::segmentation::SegmentationParams& params = {});

struct LostKeyScore {
  int runs = 0, named_table = 0, segmented_table = 0;
  std::vector<std::string> sentences;
  std::vector<std::string> segments;  // per run: the segmentation's pieces (label, footprint)
};
// The lost-key scenario with no furniture entered: the robot segments its keyframes before the question; a run
// counts when the where-is answer places the keys against a perceived furniture instance named "table" whose
// footprint overlaps the true table (IoU >= 0.5). Each run starts its own server ($ANCHORDB_BIN) on a fresh file.
// `core_density`: sent as the segmentation request's params.core_density (default: the server's default).
LostKeyScore EvaluateLostKey(int runs, std::uint64_t seed0, std::optional<double> core_density = std::nullopt);

}  // namespace anchordb::eval
