#pragma once
// A 3D occupancy tree (OctoMap, Hornung et al. 2013) behind Eigen/std types: log-odds voxels at one resolution,
// updated by ray casting point clouds from a sensor origin, with a per-voxel time of last update kept beside the
// tree (for forgetting and decay). All coordinates are in the map frame M, in metres; stamps are nanoseconds since
// the Unix epoch. OctoMap itself is included only by engine/octomap/occupancy_tree*.cc.
// Errors: Error(kUnprocessable) for impossible parameters or inputs (resolution out of range, non-finite points,
// points outside the addressable volume, an origin inside an occupied voxel), Error(kInvalidArgument) for files that
// do not decode (wrong magic, truncated, wrong tree type). A failed call leaves the tree unchanged.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace anchordb::engine {

// The sensor model and geometry of one tree (defaults as octomap_server).
struct OccupancyTreeParams {
  double resolution_m = 0.05;        // leaf edge length; [0.005, 5]
  double prob_hit = 0.7;             // P(occupied | hit), (0.5, 1)
  double prob_miss = 0.4;            // P(occupied | pass-through), (0, 0.5)
  double clamp_min = 0.12;           // lower clamping probability, (0, prob_miss]
  double clamp_max = 0.97;           // upper clamping probability, [prob_hit, 1)
  double occupancy_threshold = 0.5;  // probability above which a voxel counts occupied, (0, 1)
};

// Throws Error(kUnprocessable, field "resolution_m" / "prob_hit" / ...) when a value is out of its range.
void ValidateOccupancyTreeParams(const OccupancyTreeParams& params);

enum class VoxelState { kUnknown = 0, kFree = 1, kOccupied = 2 };
const char* VoxelStateName(VoxelState state);  // "unknown" | "free" | "occupied"

struct PointOccupancy {
  VoxelState state = VoxelState::kUnknown;
  double probability = 0.5;  // 0.5 when unknown
  double voxel_size_m = 0;   // edge of the (possibly pruned) leaf holding the point; 0 when unknown
  std::optional<std::int64_t> stamp_ns;  // last update of that voxel, when known
};

// What a ray found: the first occupied voxel, an unknown voxel (when unknown stops the ray) or nothing in range.
struct RayHit {
  VoxelState stopped_by = VoxelState::kFree;  // kOccupied: hit; kUnknown: stopped at unknown; kFree: max range
  Eigen::Vector3d end_map = Eigen::Vector3d::Zero();  // centre of the voxel where the ray ended
  double distance_m = 0;  // from the origin to end_map
};

struct Voxel {
  Eigen::Vector3d center_map = Eigen::Vector3d::Zero();
  double size_m = 0;
  float log_odds = 0;
  std::optional<std::int64_t> stamp_ns;
};

struct TreeMetadata {
  std::size_t leaves = 0;           // leaf nodes (pruned leaves count once)
  std::size_t occupied_leaves = 0;
  std::size_t nodes = 0;            // all nodes
  std::size_t memory_bytes = 0;     // liboctomap's memoryUsage()
  std::size_t stamped_voxels = 0;   // voxels with an individual last-update time
  std::optional<Eigen::Vector3d> min_map, max_map;  // bounding box of all known voxels; empty for an empty tree
};

struct InsertStats {
  std::size_t points = 0;          // in the cloud
  std::size_t free_updates = 0;    // voxels updated as free
  std::size_t occupied_updates = 0;
};

// A box in the map frame; min <= max component-wise.
struct Box3 {
  Eigen::Vector3d min_map = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_map = Eigen::Vector3d::Zero();
};

class OccupancyTree {
 public:
  // Throws as ValidateOccupancyTreeParams.
  explicit OccupancyTree(const OccupancyTreeParams& params = {});
  ~OccupancyTree();
  OccupancyTree(OccupancyTree&&) noexcept;
  OccupancyTree& operator=(OccupancyTree&&) noexcept;
  OccupancyTree Clone() const;

  const OccupancyTreeParams& params() const;
  // Changes the sensor model for later updates; the resolution must stay (kUnprocessable otherwise).
  void SetParams(const OccupancyTreeParams& params);

  // Ray casts every point of `points_map` from `origin_map`: voxels on the way become more free, the end voxel more
  // occupied; beyond `max_range_m` (<= 0: unlimited) a ray is cut and its end is not marked. Every updated voxel
  // gets `stamp_ns`. Throws kUnprocessable (tree unchanged) for a non-finite point or origin, a point or origin
  // outside the addressable volume, or an origin inside an occupied voxel.
  InsertStats InsertCloud(const std::vector<Eigen::Vector3f>& points_map, const Eigen::Vector3d& origin_map,
                          double max_range_m, std::int64_t stamp_ns);

  std::vector<PointOccupancy> Query(const std::vector<Eigen::Vector3d>& points_map) const;
  // `direction_map` need not be unit length (kUnprocessable when zero or not finite). Unknown voxels stop the ray
  // unless `ignore_unknown`.
  RayHit CastRay(const Eigen::Vector3d& origin_map, const Eigen::Vector3d& direction_map, double max_range_m,
                 bool ignore_unknown) const;
  // Occupied leaves whose centre lies in `box`, at most `limit` (then `truncated` is set).
  std::vector<Voxel> OccupiedVoxels(const Box3& box, std::size_t limit, bool* truncated = nullptr) const;
  // Every known leaf (free and occupied) whose centre lies in `box` (used by the height-band projection).
  std::vector<Voxel> KnownVoxels(const Box3& box) const;

  // Sets every known voxel in `box` to the lower clamping bound (free); unknown stays unknown. Returns the number
  // of voxels changed (at the finest resolution).
  std::size_t ClearBox(const Box3& box, std::int64_t stamp_ns);
  // Removes (back to unknown) every voxel whose last update is before `cutoff_ns`; voxels without an own stamp use
  // `base_stamp_ns()` (the time of an import). Returns the number of leaves removed.
  std::size_t ForgetOlderThan(std::int64_t cutoff_ns);

  TreeMetadata Metadata() const;
  bool empty() const;

  // The time given to voxels that have no individual stamp (an imported tree's import time); 0 by default.
  std::int64_t base_stamp_ns() const;
  void set_base_stamp_ns(std::int64_t stamp_ns);

  // The full tree with its log-odds as an OctoMap .ot stream ("# Octomap OcTree file", id OcTree).
  std::string WriteOt() const;
  // The maximum-likelihood tree as an OctoMap .bt stream (lossy: occupied / free only).
  std::string WriteBt() const;
  // Replace the tree by a decoded .ot / .bt (its resolution replaces params().resolution_m; the sensor model
  // stays). Stamps are dropped; base_stamp_ns becomes `stamp_ns`. Throws kInvalidArgument (tree unchanged).
  void ReadOt(std::string_view bytes, std::int64_t stamp_ns);
  void ReadBt(std::string_view bytes, std::int64_t stamp_ns);

  // The per-voxel stamps as (packed finest-level key, stamp) pairs, for storage; RestoreStamps replaces them.
  std::vector<std::pair<std::uint64_t, std::int64_t>> Stamps() const;
  void RestoreStamps(const std::vector<std::pair<std::uint64_t, std::int64_t>>& stamps);

  // Leaf-by-leaf equality (key, depth, log-odds within `tolerance`); for tests and round-trip checks.
  bool SameLeaves(const OccupancyTree& other, float tolerance = 0) const;

 private:
  struct Impl;
  explicit OccupancyTree(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace anchordb::engine
