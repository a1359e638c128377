#pragma once
// What an observation tells the event layer each time a keyframe is stored (thesis 3.3.4): the keyframe's raw depth
// and the background at that moment, the camera, and whether the model merged earlier models.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "schema/types.h"
#include "services/events/event_types.h"

namespace anchordb::services {

struct KeyframeNotice {
  std::string map;
  std::int64_t scene_id = 0;
  std::int64_t keyframe_id = 0;
  std::string kind;                // begin | manual | settled | end
  std::int64_t stamp_ns = 0;
  std::int64_t action_layer = 0;   // the layer this keyframe opens (begin: 0)
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
  double beta = 0.03;
  std::vector<std::int64_t> merged_scenes;  // earlier models merged into this one (empty: nothing to compare with)
  const std::vector<std::uint16_t>* depth_mm = nullptr;      // [mm], K.width * K.height, row-major
  const std::vector<std::uint16_t>* background_mm = nullptr;
};

// What the analysis of one keyframe found: the events it created, how many segments it judged, and the action layer
// the keyframe closed (nullopt for a begin keyframe, or when no keyframe opened a layer before it).
struct KeyframeAnalysis {
  std::vector<EventView> events;
  int segments = 0;
  std::optional<std::int64_t> action_layer;
};

class KeyframeListener {
 public:
  virtual ~KeyframeListener() = default;
  // Runs after the keyframe is stored (in its own transactions); the summary goes into the frame's response.
  virtual KeyframeAnalysis OnKeyframe(const KeyframeNotice& notice) = 0;
};

}  // namespace anchordb::services
