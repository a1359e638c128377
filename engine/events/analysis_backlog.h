#pragma once
// What a map's backlog of keyframe analyses does to its writers and to the analysis workers (issue 33; SPEC §8).
// The analyses run behind the requests (at a lower CPU priority), so on a saturated machine a map's queue can grow
// without end while frames keep coming. Two thresholds on the map's pending analyses (queued or running, not given
// up) bound it:
//   - at `catch_up_at` the map's next analyses run at the requests' priority (so that they get a share of the CPU);
//   - at `max_pending` new frames and manual keyframes of the map are refused (503 with Retry-After, nothing
//     stored) until the backlog is below it again: the writer sees the back-pressure, and the lag of the map's
//     events is bounded by max_pending analyses.
// 0 turns either off. Closing a scene is never refused (it adds at most one keyframe per scene).
#include <cstdint>

namespace anchordb::engine {

struct AnalysisBacklogLimits {
  int catch_up_at = 8;            // pending analyses of a map from which they run at request priority; 0: never
  int max_pending = 32;           // pending analyses of a map from which its new frames are refused; 0: never
};

// True when a frame or manual keyframe of a map with `pending` analyses is refused.
bool RefusesFrames(const AnalysisBacklogLimits& limits, std::int64_t pending);
// True when the map's next analysis runs at the requests' priority.
bool NeedsCatchUp(const AnalysisBacklogLimits& limits, std::int64_t pending);

}  // namespace anchordb::engine
