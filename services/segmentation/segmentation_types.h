#pragma once
// Typed requests and results of the furniture segmentation capability (thesis 5.3.1, issue 16). Map frame M, metres.
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/segmentation/furniture_segmentation.h"
#include "storage/segmentation_documents.h"

namespace anchordb::services {

// kKeyframes: the map's keyframes merged in the map frame; kOctomap: the map's OctoMap, its occupied voxels as
// points (pruned voxels filled at the tree's resolution); kCloud: a room cloud the client sends (PCD or PLY).
enum class SegmentationSource { kKeyframes, kOctomap, kCloud };

// The occupied voxel centres of a map's OctoMap, at its resolution (what the octomap source segments).
struct OccupiedCloud {
  std::vector<Eigen::Vector3f> points_m;
  double resolution_m = 0.05;
  bool truncated = false;  // the tree held more occupied voxels than one listing gives
};

struct SegmentationRequest {
  SegmentationSource source = SegmentationSource::kKeyframes;
  // kKeyframes: these keyframes of the map (each with its merge-corrected camera), or, empty, the begin and end
  // keyframes among the newest `max_keyframes` (a person may stand in the static background of the ones between).
  // Each keyframe gives its own depth image (not its model's static background, where a person who stood still may
  // linger).
  std::vector<std::int64_t> keyframes;
  int max_keyframes = 200;
  double max_range_m = 3.5;  // depth beyond this is left out (the sensor's noise grows with the square of depth)
  // Classify with this stored 3D shape model (verification mode). None: with the newest stored shape model when
  // there is one and `use_stored_shape_model`, else by shape alone.
  std::optional<std::string> shape_model;
  bool use_stored_shape_model = true;
  // kCloud: the room cloud (map frame, metres) as PCD or PLY bytes; decoded and checked when the job is submitted
  // and held in memory for it (not in the jobs table). With `skip_nonfinite` NaN / infinite points are left out;
  // without, they are an error.
  std::string cloud_bytes;
  bool skip_nonfinite = false;
  double match_iou = 0.3;  // a segment whose footprint overlaps a known piece this much updates it
  engine::segmentation::SegmentationParams params;
};

struct CategoryShare {
  std::string category;  // id of the grounding knowledge table
  double probability = 0.0;
};

struct FurnitureInstanceView {
  std::int64_t id = 0;         // the instance id (GET /instances/{id} shows the same piece)
  bool perceived = true;       // false: entered by an operator (no segmentation changes it)
  std::string label;           // most probable category
  double label_probability = 0.0;
  std::vector<CategoryShare> categories;  // p(f), most probable first
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // footprint centre
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();    // along its own axes
  double yaw_rad = 0.0;
  double min_z_m = 0.0, height_m = 0.0;
  std::string classifier;                 // "geometry", "shape_model:<name>", "operator"
  std::vector<std::int64_t> evidence;     // keyframes that saw it
  std::int64_t observations = 0;          // segmentations that found it
  std::int64_t points = 0;                // of its stored cloud
  std::int64_t updated_ns = 0;
};

// One segment of a segmentation run and what became of it.
struct SegmentOutcome {
  std::string action;  // "created" | "updated" | "kept_operator" (overlaps an operator's piece: left alone)
  FurnitureInstanceView instance;  // as stored after the run (the operator's piece for kept_operator)
};

struct SegmentationOutcome {
  std::string source;  // "keyframes" | "octomap" | "cloud"
  std::optional<std::string> shape_model;  // the shape model that classified the segments (none: by shape alone)
  bool octomap_truncated = false;  // the octomap source gave only part of its occupied voxels
  std::size_t input_points = 0, thinned_points = 0, remaining_points = 0;
  int bridges_cut = 0;
  std::vector<std::string> planes;  // roles, in the order found
  int small_clusters = 0, flying_dropped = 0;
  std::optional<double> floor_z_m;
  std::vector<SegmentOutcome> segments;
  double seconds = 0.0;  // segmentation time (a figure, never a decision input)
};

}  // namespace anchordb::services
