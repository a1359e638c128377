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
  std::int64_t keyframes_uncommitted = 0;  // integrated into `tree` since the stored version
  engine::OccupancyTree tree;
};

template <typename F>
auto OctomapService::Mutate(const std::string& map, bool create_if_missing, F&& change) {
  std::lock_guard<std::mutex> one_writer(write_mutex_);
  std::shared_ptr<Entry> entry = Load(map, create_if_missing);
  std::unique_lock<std::shared_mutex> lock(entry->mutex);
  try {
    auto result = change(*entry);
    OctomapInfo info = CommitLocked(map, entry);
    return std::make_pair(std::move(result), std::move(info));
  } catch (...) {
    // The cached tree may hold a change that was not stored: the next use decodes the stored one (and the next
    // Follow integrates again the keyframes that were pending in it).
    DropCached(map, entry);
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
