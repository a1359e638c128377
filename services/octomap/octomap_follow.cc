// The tree follows the memory: keyframes in (octomap_from_keyframes), removed objects' voxels out.
#include <algorithm>
#include <cmath>
#include <optional>

#include "engine/scene/projection.h"
#include "schema/error.h"
#include "services/octomap/octomap_service.h"
#include "services/octomap/octomap_service_internal.h"
#include "services/scene/keyframe_listener.h"
#include "storage/octomap_repository.h"

namespace anchordb::services {

bool OctomapService::HasTree(const std::string& map) {
  return store_.Read([&](storage::Connection& c) { return storage::FindOctomap(c, map, false); }).has_value();
}

FollowReport OctomapService::Follow(const std::string& map) {
  FollowReport report;
  // Progress from the cached tree when there is one (it may be ahead of the stored version), else the stored row.
  const auto progress = [&]() -> std::optional<std::pair<std::int64_t, std::int64_t>> {
    if (!HasTree(map)) return std::nullopt;
    return Inspect(map, [](Entry& e) { return std::make_pair(e.keyframes_through, e.events_through); });
  };
  if (settings_.from_keyframes) {
    const auto start = progress();
    std::int64_t through = start ? start->first : 0;
    for (;;) {
      const std::vector<std::int64_t> ids =
          store_.Read([&](storage::Connection& c) { return storage::KeyframeIdsAfter(c, map, through, 16); });
      if (ids.empty()) break;
      std::vector<KeyframeInTree> batch;
      for (const std::int64_t id : ids) {
        const std::optional<KeyframeNotice> kf =
            store_.Read([&](storage::Connection& c) { return LoadKeyframeNotice(c, map, id); });
        KeyframeInTree& k = batch.emplace_back();
        k.keyframe_id = id;
        if (kf) {
          k.points_map = engine::BackProjectRaw(kf->depth_mm, 1000.0, kf->K, kf->X_MapCamera);
          k.origin_map = kf->X_MapCamera.translation();
          k.stamp_ns = kf->stamp_ns;
        }
      }
      report.keyframes_integrated += IntegrateKeyframes(map, batch);
      through = ids.back();
    }
  }
  const auto followed = progress();
  if (!followed) return report;  // no tree: nothing to clear
  const std::int64_t events_through = followed->second;
  const std::vector<storage::RemovedSegment> removed = store_.Read(
      [&](storage::Connection& c) { return storage::RemovedSegmentsAfter(c, map, events_through, 1000); });
  const std::int64_t last_event = store_.Read([&](storage::Connection& c) { return storage::LastEventId(c, map); });
  if (removed.empty()) {
    // Nothing to clear: the progress over the other events is stored with the next commit.
    if (last_event > events_through) {
      std::lock_guard<std::mutex> one_writer(write_mutex_);
      std::shared_ptr<Entry> entry = Load(map, false);
      std::unique_lock<std::shared_mutex> lock(entry->mutex);
      entry->events_through = std::max(entry->events_through, last_event);
    }
    return report;
  }
  Mutate(map, false, [&](Entry& e) {
    const double r = e.tree.params().resolution_m;
    for (const storage::RemovedSegment& s : removed) {
      // Half a voxel around the object, above the bottom voxel layer (the table or floor it stood on stays).
      const engine::Box3 box{{s.min_m[0] - r / 2, s.min_m[1] - r / 2, s.min_m[2] + r},
                             {s.max_m[0] + r / 2, s.max_m[1] + r / 2, s.max_m[2] + r / 2}};
      if ((box.min_map.array() <= box.max_map.array()).all()) {
        report.voxels_cleared += e.tree.ClearBox(box, clock_.NowNs());
      }
      ++report.removal_events;
      e.events_through = std::max(e.events_through, s.event_id);
    }
    if (removed.size() < 1000) e.events_through = std::max(e.events_through, last_event);
    return 0;
  });
  return report;
}

}  // namespace anchordb::services
