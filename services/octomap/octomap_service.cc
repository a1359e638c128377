#include "services/octomap/octomap_service.h"
#include "services/octomap/octomap_service_internal.h"

#include <cmath>
#include <limits>

#include "schema/error.h"
#include "services/common/cloud_bytes.h"
#include "services/common/require.h"
#include "storage/octomap_repository.h"

namespace anchordb::services {

namespace {

engine::OccupancyTreeParams ParamsOf(const storage::OctomapRecord& r) {
  engine::OccupancyTreeParams p;
  p.resolution_m = r.resolution_m;
  p.prob_hit = r.prob_hit;
  p.prob_miss = r.prob_miss;
  p.clamp_min = r.clamp_min;
  p.clamp_max = r.clamp_max;
  p.occupancy_threshold = r.occupancy_threshold;
  return p;
}

[[noreturn]] void NoTree(const std::string& map) {
  throw Error(ErrorCode::kNotFound,
              "map '" + map + "' has no octomap (PUT /v1/maps/" + map + "/octomap creates or imports one)", "octomap");
}

const engine::Box3 kEverywhere{Eigen::Vector3d::Constant(-1e9), Eigen::Vector3d::Constant(1e9)};

}  // namespace

OctomapService::OctomapService(storage::Store& store, OctomapSettings settings, const Clock& clock,
                               GridService* grid)
    : store_(store), settings_(settings), clock_(clock), grid_(grid) {}
OctomapService::~OctomapService() = default;

std::shared_ptr<OctomapService::Entry> OctomapService::Load(const std::string& map, bool create_if_missing) {
  const std::optional<storage::OctomapRecord> row = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::FindOctomap(c, map, false);
  });
  if (!row) {
    if (!create_if_missing) NoTree(map);
    auto fresh = std::make_shared<Entry>();
    fresh->max_range_m = settings_.max_range_m;
    return fresh;
  }
  {
    std::lock_guard<std::mutex> lock(cache_mutex_);
    if (const auto it = cache_.find(map); it != cache_.end() && it->second->version == row->version) return it->second;
  }
  const std::optional<storage::OctomapRecord> full =
      store_.Read([&](storage::Connection& c) { return storage::FindOctomap(c, map, true); });
  if (!full) NoTree(map);
  auto entry = std::make_shared<Entry>();
  entry->tree = engine::OccupancyTree(ParamsOf(*full));
  const std::string ot = storage::DecodeOctomapTree(full->tree_blob, map);
  if (!ot.empty()) entry->tree.ReadOt(ot, full->base_stamp_ns);
  entry->tree.set_base_stamp_ns(full->base_stamp_ns);
  entry->tree.RestoreStamps(storage::DecodeOctomapStamps(full->stamps_blob, map));
  entry->version = full->version;
  entry->max_range_m = full->max_range_m;
  entry->created_ns = full->created_ns;
  entry->updated_ns = full->updated_ns;
  entry->stored_bytes = full->tree_bytes + full->stamps_bytes;
  entry->keyframes_through = full->keyframes_through;
  entry->events_through = full->events_through;
  std::lock_guard<std::mutex> lock(cache_mutex_);
  std::shared_ptr<Entry>& cached = cache_[map];
  if (!cached || cached->version < entry->version) cached = entry;
  return entry;
}

namespace {

template <typename CachedTree>  // OctomapService::Entry (private to the service)
OctomapInfo InfoOf(const std::string& map, const CachedTree& e) {
  OctomapInfo info;
  info.map = map;
  info.version = e.version;
  info.params = e.tree.params();
  info.max_range_m = e.max_range_m;
  info.metadata = e.tree.Metadata();
  info.stored_bytes = e.stored_bytes;
  info.created_ns = e.created_ns;
  info.updated_ns = e.updated_ns;
  info.keyframes_through = e.keyframes_through;
  info.keyframes_uncommitted = e.keyframes_uncommitted;
  return info;
}

}  // namespace

OctomapInfo OctomapService::CommitLocked(const std::string& map, const std::shared_ptr<Entry>& entry) {
  const std::int64_t now = clock_.NowNs();
  const engine::TreeMetadata m = entry->tree.Metadata();
  storage::OctomapRecord r;
  r.map_id = map;
  const engine::OccupancyTreeParams& p = entry->tree.params();
  r.resolution_m = p.resolution_m;
  r.prob_hit = p.prob_hit;
  r.prob_miss = p.prob_miss;
  r.clamp_min = p.clamp_min;
  r.clamp_max = p.clamp_max;
  r.occupancy_threshold = p.occupancy_threshold;
  r.max_range_m = entry->max_range_m;
  r.tree_blob = storage::EncodeOctomapTree(entry->tree.empty() ? std::string() : entry->tree.WriteOt());
  r.stamps_blob = storage::EncodeOctomapStamps(entry->tree.Stamps());
  r.base_stamp_ns = entry->tree.base_stamp_ns();
  r.leaves = static_cast<std::int64_t>(m.leaves);
  r.occupied_leaves = static_cast<std::int64_t>(m.occupied_leaves);
  r.keyframes_through = entry->keyframes_through;
  r.events_through = entry->events_through;
  r.created_ns = entry->version == 0 ? now : entry->created_ns;
  r.updated_ns = now;
  const std::optional<std::int64_t> expected =
      entry->version == 0 ? std::nullopt : std::optional<std::int64_t>(entry->version);
  const std::int64_t version = store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::UpsertOctomap(c, r, expected);
  });
  entry->version = version;
  entry->created_ns = r.created_ns;
  entry->updated_ns = now;
  entry->stored_bytes = static_cast<std::int64_t>(r.tree_blob.size() + r.stamps_blob.size());
  entry->keyframes_uncommitted = 0;
  {
    std::lock_guard<std::mutex> cache_lock(cache_mutex_);
    cache_[map] = entry;
  }
  return InfoOf(map, *entry);
}

void OctomapService::DropCached(const std::string& map, const std::shared_ptr<Entry>& entry) {
  std::lock_guard<std::mutex> cache_lock(cache_mutex_);
  if (const auto it = cache_.find(map); it != cache_.end() && it->second == entry) cache_.erase(it);
}

std::size_t OctomapService::IntegrateKeyframes(const std::string& map, const std::vector<KeyframeInTree>& keyframes,
                                               bool commit) {
  std::lock_guard<std::mutex> one_writer(write_mutex_);
  std::shared_ptr<Entry> entry = Load(map, true);
  std::unique_lock<std::shared_mutex> lock(entry->mutex);
  std::size_t integrated = 0;
  try {
    for (const KeyframeInTree& k : keyframes) {
      if (k.keyframe_id <= entry->keyframes_through) continue;  // already in the tree
      if (!k.points_map.empty()) {
        // A keyframe taken from inside what the tree holds as occupied is skipped, not fatal.
        try {
          entry->tree.InsertCloud(k.points_map, k.origin_map, entry->max_range_m, k.stamp_ns);
          ++integrated;
        } catch (const Error& error) {
          if (error.code() != ErrorCode::kUnprocessable) throw;
        }
      }
      entry->keyframes_through = k.keyframe_id;
      ++entry->keyframes_uncommitted;
    }
    // A tree not stored yet is not cached either: store it at once so that the next batch finds it.
    if (commit || entry->version == 0 || entry->keyframes_uncommitted >= settings_.keyframes_per_commit) {
      if (entry->keyframes_uncommitted > 0 || entry->version == 0) CommitLocked(map, entry);
    }
  } catch (...) {
    DropCached(map, entry);
    throw;
  }
  return integrated;
}

std::size_t OctomapService::CommitPending() {
  std::vector<std::pair<std::string, std::shared_ptr<Entry>>> dirty;
  {
    std::lock_guard<std::mutex> cache_lock(cache_mutex_);
    for (const auto& [map, entry] : cache_) dirty.emplace_back(map, entry);
  }
  std::size_t stored = 0;
  for (const auto& [map, entry] : dirty) {
    std::lock_guard<std::mutex> one_writer(write_mutex_);
    std::unique_lock<std::shared_mutex> lock(entry->mutex);
    if (entry->keyframes_uncommitted == 0) continue;
    try {
      CommitLocked(map, entry);
      ++stored;
    } catch (const std::exception&) {
      DropCached(map, entry);  // the keyframes are integrated again at the next start
    }
  }
  return stored;
}

OctomapInfo OctomapService::Configure(const std::string& map, const OctomapConfig& config) {
  return Mutate(map, true, [&](Entry& e) {
           engine::OccupancyTreeParams p = e.tree.params();
           p.resolution_m = config.resolution_m.value_or(p.resolution_m);
           p.prob_hit = config.prob_hit.value_or(p.prob_hit);
           p.prob_miss = config.prob_miss.value_or(p.prob_miss);
           p.clamp_min = config.clamp_min.value_or(p.clamp_min);
           p.clamp_max = config.clamp_max.value_or(p.clamp_max);
           p.occupancy_threshold = config.occupancy_threshold.value_or(p.occupancy_threshold);
           const double range = config.max_range_m.value_or(e.max_range_m);
           if (!std::isfinite(range) || range <= 0 || range > 1000) {
             throw Error(ErrorCode::kUnprocessable, "max_range_m must be in (0, 1000] m", "max_range_m");
           }
           engine::ValidateOccupancyTreeParams(p);
           if (p.resolution_m != e.tree.params().resolution_m) {
             if (!e.tree.empty()) {
               throw Error(ErrorCode::kConflict, "the resolution of a tree that holds voxels cannot change",
                           "resolution_m");
             }
             e.tree = engine::OccupancyTree(p);
           } else {
             e.tree.SetParams(p);
           }
           e.max_range_m = range;
           return 0;
         })
      .second;
}

OctomapInfo OctomapService::Import(const std::string& map, TreeFileFormat format, const std::string& bytes) {
  return Mutate(map, true, [&](Entry& e) {
           // Either read replaces the tree (and its stamps) only when the file decodes.
           if (format == TreeFileFormat::kBt) e.tree.ReadBt(bytes, clock_.NowNs());
           else e.tree.ReadOt(bytes, clock_.NowNs());
           return 0;
         })
      .second;
}

OctomapInfo OctomapService::Get(const std::string& map) {
  return Inspect(map, [&](Entry& e) {
    return InfoOf(map, e);
  });
}

ExportedLayer OctomapService::Export(const std::string& map, TreeFileFormat format) {
  return Inspect(map, [&](Entry& e) {
    ExportedLayer out;
    out.format = BytesFormat::kOctomapBinary;
    out.body = format == TreeFileFormat::kBt ? e.tree.WriteBt() : e.tree.WriteOt();
    out.octomap_version = e.version;
    out.file_name = map + (format == TreeFileFormat::kBt ? ".bt" : ".ot");
    return out;
  });
}

ExportedLayer OctomapService::ExportOccupiedCloud(const std::string& map, engine::CloudFormat format) {
  const VoxelsResult voxels = OccupiedVoxels(map, kEverywhere, std::nullopt);
  std::vector<Eigen::Vector3f> points;
  points.reserve(voxels.voxels.size());
  for (const engine::Voxel& v : voxels.voxels) points.push_back(v.center_map.cast<float>());
  ExportedLayer out = CloudBytes(points, format);
  out.truncated = voxels.truncated;
  return out;
}

InsertCloudResult OctomapService::InsertCloud(const InsertCloudRequest& request) {
  engine::DecodedCloud cloud = engine::DecodeCloud(request.body, static_cast<std::size_t>(settings_.max_points));
  Eigen::Vector3d origin_map;
  if (request.origin_map) origin_map = *request.origin_map;
  else if (cloud.has_sensor_origin) origin_map = cloud.sensor_origin.cast<double>();
  else throw Error(ErrorCode::kInvalidArgument, "the sensor origin is missing (query origin=x,y,z)", "origin");
  std::size_t skipped = 0;
  if (request.skip_nonfinite) {
    std::vector<Eigen::Vector3f> finite;
    finite.reserve(cloud.points.size());
    for (const Eigen::Vector3f& p : cloud.points) {
      if (p.allFinite()) finite.push_back(p);
    }
    skipped = cloud.points.size() - finite.size();
    cloud.points = std::move(finite);
  }
  InsertCloudResult r = InsertPoints(request.map, cloud.points, origin_map, request.max_range_m,
                                     request.stamp_ns.value_or(clock_.NowNs()));
  r.skipped_nonfinite = skipped;
  return r;
}

InsertCloudResult OctomapService::InsertPoints(const std::string& map, const std::vector<Eigen::Vector3f>& points_map,
                                               const Eigen::Vector3d& origin_map, std::optional<double> max_range_m,
                                               std::int64_t stamp_ns) {
  if (max_range_m && (!std::isfinite(*max_range_m) || *max_range_m <= 0)) {
    throw Error(ErrorCode::kUnprocessable, "max_range_m must be positive", "max_range_m");
  }
  auto [stats, info] = Mutate(map, true, [&](Entry& e) {
    return e.tree.InsertCloud(points_map, origin_map, max_range_m.value_or(e.max_range_m), stamp_ns);
  });
  InsertCloudResult r;
  r.stats = stats;
  r.octomap = std::move(info);
  return r;
}

std::vector<engine::PointOccupancy> OctomapService::Query(const std::string& map,
                                                          const std::vector<Eigen::Vector3d>& points_map) {
  if (points_map.size() > static_cast<std::size_t>(settings_.max_query_points)) {
    throw Error(ErrorCode::kPayloadTooLarge,
                "at most " + std::to_string(settings_.max_query_points) + " points per query", "points");
  }
  return Inspect(map, [&](Entry& e) { return e.tree.Query(points_map); });
}

engine::RayHit OctomapService::CastRay(const RayRequest& request) {
  return Inspect(request.map, [&](Entry& e) {
    return e.tree.CastRay(request.origin_map, request.direction_map, request.max_range_m, request.ignore_unknown);
  });
}

VoxelsResult OctomapService::OccupiedVoxels(const std::string& map, const engine::Box3& box,
                                            std::optional<std::size_t> limit) {
  const std::size_t cap = static_cast<std::size_t>(settings_.max_voxels);
  const std::size_t n = std::min(limit.value_or(cap), cap);
  return Inspect(map, [&](Entry& e) {
    VoxelsResult r;
    r.voxels = e.tree.OccupiedVoxels(box, n, &r.truncated);
    return r;
  });
}

std::vector<engine::Voxel> OctomapService::KnownVoxels(const std::string& map, const engine::Box3& box) {
  return Inspect(map, [&](Entry& e) { return e.tree.KnownVoxels(box); });
}

ClearBoxResult OctomapService::ClearBox(const std::string& map, const engine::Box3& box) {
  Load(map, false);  // 404 before anything is created
  auto [cleared, info] = Mutate(map, false, [&](Entry& e) { return e.tree.ClearBox(box, clock_.NowNs()); });
  return {cleared, std::move(info)};
}

std::size_t OctomapService::ForgetOlderThan(const std::string& map, std::int64_t cutoff_ns) {
  const bool has_tree = store_.Read([&](storage::Connection& c) { return storage::FindOctomap(c, map, false); })
                            .has_value();
  if (!has_tree) return 0;
  return Mutate(map, false, [&](Entry& e) { return e.tree.ForgetOlderThan(cutoff_ns); }).first;
}

DecayResult OctomapService::Decay(const std::string& map, double max_age_s, std::optional<std::int64_t> now_ns) {
  const std::int64_t wall = clock_.NowNs();
  if (now_ns && *now_ns > wall) throw Error(ErrorCode::kUnprocessable, "now must not lie in the future", "now");
  Load(map, false);  // 404 before anything is created
  DecayResult r;
  r.cutoff_ns = now_ns.value_or(wall) - static_cast<std::int64_t>(max_age_s * 1e9);
  auto [forgotten, info] = Mutate(map, false, [&](Entry& e) { return e.tree.ForgetOlderThan(r.cutoff_ns); });
  r.leaves_forgotten = forgotten;
  r.octomap = std::move(info);
  return r;
}

}  // namespace anchordb::services
