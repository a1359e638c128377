// The tree follows the memory: keyframes in (octomap_from_keyframes), removed objects' voxels out.
#include <cmath>

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
  std::optional<storage::OctomapRecord> row =
      store_.Read([&](storage::Connection& c) { return storage::FindOctomap(c, map, false); });
  if (settings_.from_keyframes) {
    std::int64_t through = row ? row->keyframes_through : 0;
    for (;;) {
      const std::vector<std::int64_t> ids =
          store_.Read([&](storage::Connection& c) { return storage::KeyframeIdsAfter(c, map, through, 16); });
      if (ids.empty()) break;
      for (const std::int64_t id : ids) {
        const std::optional<KeyframeNotice> kf =
            store_.Read([&](storage::Connection& c) { return LoadKeyframeNotice(c, map, id); });
        std::vector<Eigen::Vector3f> points_M;
        Eigen::Vector3d origin_M = Eigen::Vector3d::Zero();
        std::int64_t stamp_ns = 0;
        if (kf) {
          points_M = engine::BackProjectRaw(kf->depth_mm, 1000.0, kf->K, kf->X_MapCamera);
          origin_M = kf->X_MapCamera.translation();
          stamp_ns = kf->stamp_ns;
        }
        Mutate(map, true, [&](Entry& e) {
          // A keyframe taken from inside what the tree holds as occupied is skipped, not fatal.
          if (kf) {
            try {
              e.tree.InsertCloud(points_M, origin_M, e.max_range_m, stamp_ns);
              ++report.keyframes_integrated;
            } catch (const Error& error) {
              if (error.code() != ErrorCode::kUnprocessable) throw;
            }
          }
          e.keyframes_through = std::max(e.keyframes_through, id);
          return 0;
        });
        through = id;
      }
    }
    row = store_.Read([&](storage::Connection& c) { return storage::FindOctomap(c, map, false); });
  }
  if (!row) return report;  // no tree: nothing to clear
  const std::vector<storage::RemovedSegment> removed = store_.Read(
      [&](storage::Connection& c) { return storage::RemovedSegmentsAfter(c, map, row->events_through, 1000); });
  const std::int64_t last_event = store_.Read([&](storage::Connection& c) { return storage::LastEventId(c, map); });
  if (removed.empty() && last_event <= row->events_through) return report;
  Mutate(map, false, [&](Entry& e) {
    const double r = e.tree.params().resolution_m;
    for (const storage::RemovedSegment& s : removed) {
      // Half a voxel around the object, above the bottom voxel layer (the table or floor it stood on stays).
      const engine::Box3 box{{s.min_m[0] - r / 2, s.min_m[1] - r / 2, s.min_m[2] + r},
                             {s.max_m[0] + r / 2, s.max_m[1] + r / 2, s.max_m[2] + r / 2}};
      if ((box.min_M.array() <= box.max_M.array()).all()) {
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
