#pragma once
// Movement-settle detection (thesis 3.3.4): a completed movement closes an action layer. After the movable layer
// changed by at least `settle_min_change_px` pixels since the last keyframe (or as many background pixels were
// reset farther since then: a removal), it stayed within `settle_tolerance_px` for `settle_frames` frames without
// dynamic pixels -> a 'settled' keyframe is due. Pure: fed one frame's pixel counts at a time.
#include <cstdint>
#include <cstdlib>

#include "engine/scene/scene_model.h"

namespace anchordb::engine {

struct SettleParams {
  int settle_frames = 8;           // steady frames a movement needs to count as completed; 0 (or less) = off
  int settle_min_change_px = 400;  // movable pixels changed (or background pixels reset) since the last keyframe
  int settle_tolerance_px = 60;    // steady: movable count within this of the previous frame's, resets at most this
};

// The settle state of one scene model (a fresh detector: nothing moved, no previous frame).
class SettleDetector {
 public:
  // Takes the counts of one applied frame; true when a movement completed with this frame (the caller stores a
  // 'settled' keyframe and calls OnKeyframe). Always false when detection is off.
  bool OnFrame(const FrameCounts& counts, const SettleParams& params) {
    const auto movable = static_cast<std::int64_t>(counts.movable);
    bool settled = false;
    if (params.settle_frames > 0) {
      reset_since_keyframe_ += static_cast<std::int64_t>(counts.reset);
      const bool changed = std::abs(movable - movable_at_keyframe_) >= params.settle_min_change_px ||
                           reset_since_keyframe_ >= params.settle_min_change_px;
      const bool steady = previous_movable_ >= 0 && std::abs(movable - previous_movable_) <= params.settle_tolerance_px &&
                          counts.dynamic == 0 && counts.reset <= static_cast<std::size_t>(params.settle_tolerance_px);
      stable_frames_ = steady ? stable_frames_ + 1 : 0;
      settled = changed && stable_frames_ >= params.settle_frames;
    }
    previous_movable_ = movable;
    return settled;
  }

  // A keyframe was stored while the movable layer had `movable_px` pixels: the next movement is measured from it.
  void OnKeyframe(std::size_t movable_px) {
    movable_at_keyframe_ = static_cast<std::int64_t>(movable_px);
    reset_since_keyframe_ = 0;
    stable_frames_ = 0;
  }

 private:
  std::int64_t movable_at_keyframe_ = 0;
  std::int64_t reset_since_keyframe_ = 0;
  std::int64_t previous_movable_ = -1;  // -1: no frame yet
  int stable_frames_ = 0;
};

}  // namespace anchordb::engine
