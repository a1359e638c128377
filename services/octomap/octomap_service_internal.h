#pragma once
// Internal to services/octomap/*.cc: the cached tree of one map and the two ways to use it (one writer that stores
// the changed tree as the next version; readers sharing the cached one).
#include <cmath>
#include <shared_mutex>

#include "schema/error.h"
#include "services/common/require.h"
#include "services/octomap/octomap_service.h"
#include "storage/octomap_repository.h"

namespace anchordb::services {

struct OctomapService::Entry {
  std::shared_mutex mutex;  // readers share, the one writer excludes
  std::int64_t version = 0;  // 0: not stored yet
  double max_range_m = 5;
  std::int64_t created_ns = 0, updated_ns = 0;
  std::int64_t stored_bytes = 0;
  std::int64_t keyframes_through = 0, events_through = 0;
  engine::OccupancyTree tree;
};

template <typename F>
auto OctomapService::Mutate(const std::string& map, bool create_if_missing, F&& change) {
  std::lock_guard<std::mutex> one_writer(write_mutex_);
  std::shared_ptr<Entry> entry = Load(map, create_if_missing);
  std::unique_lock<std::shared_mutex> lock(entry->mutex);
  try {
    auto result = change(*entry);
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
    {
      std::lock_guard<std::mutex> cache_lock(cache_mutex_);
      cache_[map] = entry;
    }
    OctomapInfo info;
    info.map = map;
    info.version = version;
    info.params = p;
    info.max_range_m = entry->max_range_m;
    info.metadata = m;
    info.stored_bytes = entry->stored_bytes;
    info.created_ns = entry->created_ns;
    info.updated_ns = now;
    return std::make_pair(std::move(result), std::move(info));
  } catch (...) {
    // The cached tree may hold a change that was not stored: the next use decodes the stored one.
    std::lock_guard<std::mutex> cache_lock(cache_mutex_);
    if (const auto it = cache_.find(map); it != cache_.end() && it->second == entry) cache_.erase(it);
    throw;
  }
}

template <typename F>
auto OctomapService::Inspect(const std::string& map, F&& look) {
  std::shared_ptr<Entry> entry = Load(map, false);
  std::shared_lock<std::shared_mutex> lock(entry->mutex);
  return look(*entry);
}

}  // namespace anchordb::services
