#pragma once
// The octomap capability (SPEC 4.9): one 3D occupancy tree per map, stored as a versioned row (storage/
// octomap_repository.h), computed by engine/octomap. Clouds are decoded and trees mutated outside the store's write
// lock; one octomap write runs at a time; readers query a cached decoded tree while its version is the stored one.
// Errors (anchordb::Error): kNotFound for an unknown map (field "map") or a map without a tree (field "octomap");
// kInvalidArgument for bodies that do not decode; kUnprocessable for impossible values (engine/octomap);
// kPayloadTooLarge beyond the limits of OctomapSettings. A failed call changes nothing.
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "engine/cloud/cloud_io.h"
#include "schema/clock.h"
#include "services/common/exported_bytes.h"
#include "services/grid/grid_service.h"
#include "services/octomap/octomap_settings.h"
#include "services/octomap/octomap_types.h"
#include "storage/store.h"

namespace anchordb::services {

class OctomapService {
 public:
  // `grid` (may be null: no projection) stores the projected layers; it must outlive the service.
  OctomapService(storage::Store& store, OctomapSettings settings, const Clock& clock = SystemClock::Instance(),
                 GridService* grid = nullptr);
  ~OctomapService();

  // Creates the map's tree (empty) or changes its sensor model and range; the resolution of a tree that holds
  // voxels cannot change (kConflict, field "resolution_m").
  OctomapInfo Configure(const std::string& map, const OctomapConfig& config);
  // Replaces the map's tree by a decoded .bt / .ot file (its resolution); the sensor model stays.
  OctomapInfo Import(const std::string& map, TreeFileFormat format, const std::string& bytes);
  OctomapInfo Get(const std::string& map);
  // The tree as .bt or .ot, with its version and a file name.
  ExportedLayer Export(const std::string& map, TreeFileFormat format);
  // The occupied voxel centres as a point cloud (at most max_voxels; X-Truncated header when cut).
  ExportedLayer ExportOccupiedCloud(const std::string& map, engine::CloudFormat format);
  // Creates the tree with the defaults when the map has none.
  InsertCloudResult InsertCloud(const InsertCloudRequest& request);
  // Inserts points already in the map frame (keyframe clouds); as InsertCloud.
  InsertCloudResult InsertPoints(const std::string& map, const std::vector<Eigen::Vector3f>& points_map,
                                 const Eigen::Vector3d& origin_map, std::optional<double> max_range_m,
                                 std::int64_t stamp_ns);

  std::vector<engine::PointOccupancy> Query(const std::string& map, const std::vector<Eigen::Vector3d>& points_map);
  engine::RayHit CastRay(const RayRequest& request);
  VoxelsResult OccupiedVoxels(const std::string& map, const engine::Box3& box, std::optional<std::size_t> limit);
  // Known leaves in a box (for the height-band projection).
  std::vector<engine::Voxel> KnownVoxels(const std::string& map, const engine::Box3& box);
  ClearBoxResult ClearBox(const std::string& map, const engine::Box3& box);
  // Voxels not updated since `cutoff_ns` go back to unknown; returns how many leaves went (0 without a tree).
  std::size_t ForgetOlderThan(const std::string& map, std::int64_t cutoff_ns);
  // The forgetting policy's decay: voxels not updated for `max_age_s` before `now_ns` (default the clock's now; not
  // in the future: kUnprocessable field "now") go back to unknown. kNotFound without a tree.
  DecayResult Decay(const std::string& map, double max_age_s, std::optional<std::int64_t> now_ns);

  // Projects height bands into occupancy layers (octomap_projection.cc); kUnprocessable for an empty tree without
  // a grid to follow, bad bands (field "bands") or a rotated grid.
  ProjectResult Project(const ProjectRequest& request);

  // Brings the map's tree up to date with the rest of the memory (octomap_follow.cc): with octomap_from_keyframes,
  // every keyframe stored since the last call is back-projected and ray-cast from its camera (max range: the map's);
  // for every 'removed' change event since then, the voxels of the removed object's segment box are cleared (its
  // bottom voxel layer kept: the surface it stood on). Progress is stored with the tree, so a restart resumes. A map
  // without a tree gets one only when there is a keyframe to integrate.
  // Keyframes are integrated in batches of up to 16 and the tree is stored once per octomap_keyframes_per_commit
  // keyframes (at once for a map that has no stored tree yet); any other write stores what is pending with it.
  FollowReport Follow(const std::string& map);
  bool HasTree(const std::string& map);
  // Ray-casts keyframe clouds (ids ascending, past the tree's keyframes_through) into the map's tree, creating it
  // with the defaults; stores the tree as Follow does (or at once with `commit`). Returns how many were integrated
  // (a keyframe taken from inside what the tree holds as occupied is skipped). The path of Follow after loading.
  std::size_t IntegrateKeyframes(const std::string& map, const std::vector<KeyframeInTree>& keyframes, bool commit = false);
  // Stores every tree holding integrated keyframes not yet stored (the server's stop); returns how many trees.
  std::size_t CommitPending();

  // ---- point clouds out (cloud_exports.cc), as PCD / PLY of x, y, z [m]
  // A stored keyframe's raw depth (or, with `background`, the scene model's static background when it was stored)
  // back-projected with its camera, in the map frame (merge-corrected camera pose) or the camera's optical frame.
  // kNotFound field "keyframe".
  ExportedLayer KeyframeCloud(const std::string& map, std::int64_t keyframe_id, bool background, bool map_frame,
                              engine::CloudFormat format);
  // The stored point sample (up to 256 points, map frame) of a change event's segment. kNotFound field "event";
  // kUnprocessable when the event has no segment.
  ExportedLayer EventSegmentCloud(const std::string& map, std::int64_t event_id, engine::CloudFormat format);

  const OctomapSettings& settings() const { return settings_; }

 private:
  struct Entry;
  // The map's tree at the stored version (from the cache or decoded); kNotFound without one.
  std::shared_ptr<Entry> Load(const std::string& map, bool create_if_missing);
  template <typename F>
  auto Mutate(const std::string& map, bool create_if_missing, F&& change);
  // Stores `entry` (changed in place by the caller, who holds write_mutex_ and the entry's lock) as the map's next
  // version and caches it. Throws as the store; the caller then drops the entry from the cache.
  OctomapInfo CommitLocked(const std::string& map, const std::shared_ptr<Entry>& entry);
  void DropCached(const std::string& map, const std::shared_ptr<Entry>& entry);
  template <typename F>
  auto Inspect(const std::string& map, F&& look);

  storage::Store& store_;
  OctomapSettings settings_;
  const Clock& clock_;
  GridService* grid_;
  std::mutex write_mutex_;  // one octomap change at a time
  std::mutex cache_mutex_;
  std::map<std::string, std::shared_ptr<Entry>> cache_;
};

}  // namespace anchordb::services
