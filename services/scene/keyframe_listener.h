#pragma once
// What an observation tells the event layer each time a keyframe is stored (thesis 3.3.4), and how the keyframe's
// change analysis is queued. The scene service records the analysis in the keyframe's own write transaction
// (KeyframeListener::Enqueue, a durable queue row) and answers without waiting for it; the analysis runs later, one
// map's keyframes in the order they were stored, reading the keyframe's depth and background as stored
// (LoadKeyframeNotice). A caller that needs the events waits for them explicitly (KeyframeListener::Await).
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "schema/types.h"
#include "services/events/event_types.h"
#include "storage/connection.h"

namespace anchordb::services {

// Everything the analysis of one keyframe reads about the keyframe itself.
struct KeyframeNotice {
  std::string map;
  std::int64_t scene_id = 0;
  std::int64_t keyframe_id = 0;
  std::string kind;                // begin | manual | settled | end
  std::int64_t stamp_ns = 0;
  std::int64_t action_layer = 0;   // the layer this keyframe opens (begin: 0)
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();  // the model's camera (merge-corrected) in the map
  double beta = 0.03;
  std::vector<std::int64_t> merged_scenes;  // earlier models merged into this one (empty: nothing to compare with)
  std::vector<std::uint16_t> depth_mm;       // [mm], K.width * K.height, row-major: the keyframe's raw depth
  std::vector<std::uint16_t> background_mm;  // [mm]: the model's static background when the keyframe was stored
};

// The stored keyframe `keyframe_id` of `map` as its analysis sees it (services/scene/keyframe_notice.cc): its images
// decoded from the keyframe row, the camera, pose, beta and merged models from its scene's row. nullopt when the
// keyframe no longer exists (forgotten, its scene or map deleted).
std::optional<KeyframeNotice> LoadKeyframeNotice(storage::Connection& c, const std::string& map, std::int64_t keyframe_id);

// What the analysis of one keyframe found: the events it created, how many segments it judged, and the action layer
// the keyframe closed (nullopt for a begin keyframe, or when no keyframe opened a layer before it).
struct KeyframeAnalysis {
  std::vector<EventView> events;
  int segments = 0;
  std::optional<std::int64_t> action_layer;
};

enum class AnalysisState {
  kPending,  // queued or running (possibly retrying after a failure: attempts, last_error)
  kDone,     // written; `result` holds it when this process ran it (after a restart only the state is known)
  kFailed,   // given up after a non-transient error (last_error); the keyframe stays stored
  kSkipped,  // the keyframe was deleted before its analysis ran
};  // names: kAnalysisStateNames (scene_types.h)

struct KeyframeAnalysisStatus {
  AnalysisState state = AnalysisState::kPending;
  std::int64_t keyframe_id = 0;
  std::optional<KeyframeAnalysis> result;  // kDone
  int attempts = 0;                        // failed attempts so far
  std::optional<std::string> last_error;
};

// A keyframe as the scene service hands it to the queue.
struct QueuedKeyframe {
  std::string map;
  std::int64_t scene_id = 0;
  std::int64_t keyframe_id = 0;
  std::int64_t enqueued_ns = 0;
};

class KeyframeListener {
 public:
  virtual ~KeyframeListener() = default;
  // Before a frame or a manual keyframe of `map` changes anything: throws Error(kOverloaded) (503 with Retry-After)
  // while the map's backlog of analyses is at the listener's bound (engine/events/analysis_backlog.h). A listener
  // that forwards to another forwards this too.
  virtual void Admit(const std::string& map) = 0;
  // In the write transaction that stores the keyframe: its analysis is queued durably with it.
  virtual void Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) = 0;
  // After that transaction committed: the analysis may start.
  virtual void Enqueued(const std::string& map) = 0;
  // Waits until the keyframe's analysis is done, failed or skipped, at most the listener's configured bound; a status
  // kPending when it was not done by then. Never holds a lock the scene service needs.
  virtual KeyframeAnalysisStatus Await(std::int64_t keyframe_id) = 0;
};

}  // namespace anchordb::services
