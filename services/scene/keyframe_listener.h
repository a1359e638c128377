#pragma once
// What an observation tells the event layer each time a keyframe is stored (thesis 3.3.4): the keyframe's raw depth
// and the background at that moment, the camera, and whether the model merged earlier models.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "schema/json_io.h"
#include "schema/types.h"
#include "services/common/transitional_json.h"

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
  const std::vector<std::uint16_t>* depth_mm = nullptr;
  const std::vector<std::uint16_t>* background_mm = nullptr;
};

class KeyframeListener {
 public:
  virtual ~KeyframeListener() = default;
  // Runs after the keyframe is stored; returns a summary for the response (events created).
  virtual Json OnKeyframe(const KeyframeNotice& notice) = 0;
};

}  // namespace anchordb::services
