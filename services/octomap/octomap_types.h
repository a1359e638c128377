#pragma once
// Typed requests and results of the octomap capability (services/octomap/octomap_service.h). Map frame M, metres,
// nanoseconds since the Unix epoch.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/octomap/height_bands.h"
#include "engine/octomap/occupancy_tree.h"
#include "services/grid/grid_types.h"

namespace anchordb::services {

// Per-map parameters; unset fields keep the stored (or default) value.
struct OctomapConfig {
  std::optional<double> resolution_m, prob_hit, prob_miss, clamp_min, clamp_max, occupancy_threshold;
  std::optional<double> max_range_m;  // rays longer than this are cut (their end not marked) [m]
};

struct OctomapInfo {
  std::string map;
  std::int64_t version = 0;
  engine::OccupancyTreeParams params;
  double max_range_m = 0;
  engine::TreeMetadata metadata;
  std::int64_t stored_bytes = 0;  // the compressed tree and stamps in the SQLite file
  std::int64_t created_ns = 0, updated_ns = 0;
  std::int64_t keyframes_through = 0;      // the newest keyframe integrated (octomap_from_keyframes)
  std::int64_t keyframes_uncommitted = 0;  // integrated keyframes not yet in the stored version (octomap_keyframes_per_commit)
};

// One stored keyframe's depth, back-projected in the map frame, for the tree.
struct KeyframeInTree {
  std::int64_t keyframe_id = 0;
  std::vector<Eigen::Vector3f> points_map;  // empty: the keyframe is gone (its id still counts as followed)
  Eigen::Vector3d origin_map = Eigen::Vector3d::Zero();
  std::int64_t stamp_ns = 0;
};

enum class TreeFileFormat { kBt, kOt };

struct InsertCloudRequest {
  std::string map;
  std::string body;                        // PCD (any DATA kind) or PLY
  std::optional<Eigen::Vector3d> origin_map; // the sensor origin; else the cloud's own viewpoint
  std::optional<double> max_range_m;       // else the map's
  bool skip_nonfinite = false;             // drop NaN / inf points (organised clouds) instead of refusing the cloud
  std::optional<std::int64_t> stamp_ns;    // else now
};

struct InsertCloudResult {
  OctomapInfo octomap;
  engine::InsertStats stats;
  std::size_t skipped_nonfinite = 0;
};

struct RayRequest {
  std::string map;
  Eigen::Vector3d origin_map = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_map = Eigen::Vector3d::UnitX();
  double max_range_m = 10;
  bool ignore_unknown = false;
};

struct VoxelsResult {
  std::vector<engine::Voxel> voxels;
  bool truncated = false;
};

struct ClearBoxResult {
  std::size_t voxels_cleared = 0;
  OctomapInfo octomap;
};

// Height bands -> 2D occupancy layers. The grid is that of `like` (an occupancy layer), else of the map's first
// occupancy layer that is not a band, else the tree's bounding box at `resolution_m` (default: the tree's).
struct ProjectRequest {
  std::string map;
  std::vector<engine::HeightBand> bands;
  std::optional<std::string> like;
  std::optional<double> resolution_m;
};

struct ProjectedBand {
  LayerInfo layer;
  engine::HeightBand band;
  engine::BandCounts cells;
};

struct ProjectResult {
  GridGeometry geometry;
  std::string geometry_from;  // "layer <name>" or "tree"
  std::vector<ProjectedBand> bands;
};

struct DecayResult {
  std::size_t leaves_forgotten = 0;
  std::int64_t cutoff_ns = 0;
  OctomapInfo octomap;
};

// What following the rest of the memory did to a map's tree (OctomapService::Follow).
struct FollowReport {
  std::size_t keyframes_integrated = 0;  // stored keyframes ray-cast into the tree (octomap_from_keyframes)
  std::size_t removal_events = 0;        // 'removed' change events whose object's voxels were cleared
  std::size_t voxels_cleared = 0;
};

}  // namespace anchordb::services
