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

// What a detector remembers between frames (a fresh one: nothing moved, no previous frame).
struct SettleState {
  std::int64_t movable_at_keyframe = 0;   // movable pixels when the last keyframe was stored
  std::int64_t reset_since_keyframe = 0;  // background pixels reset farther since then
  std::int64_t previous_movable = -1;     // movable pixels of the previous frame; -1: no frame yet
  int stable_frames = 0;                  // steady frames in a row
  bool operator==(const SettleState&) const = default;
};

// The settle state of one scene model.
class SettleDetector {
 public:
  SettleDetector() = default;
  // A detector that continues from `state` (a journalled model's, see services/scene).
  explicit SettleDetector(const SettleState& state) : s_(state) {}
  const SettleState& state() const { return s_; }

  // Takes the counts of one applied frame; true when a movement completed with this frame (the caller stores a
  // 'settled' keyframe and calls OnKeyframe). Always false when detection is off.
  bool OnFrame(const FrameCounts& counts, const SettleParams& params) {
    const auto movable = static_cast<std::int64_t>(counts.movable);
    bool settled = false;
    if (params.settle_frames > 0) {
      s_.reset_since_keyframe += static_cast<std::int64_t>(counts.reset);
      const bool changed = std::abs(movable - s_.movable_at_keyframe) >= params.settle_min_change_px ||
                           s_.reset_since_keyframe >= params.settle_min_change_px;
      const bool steady = s_.previous_movable >= 0 && std::abs(movable - s_.previous_movable) <= params.settle_tolerance_px &&
                          counts.dynamic == 0 && counts.reset <= static_cast<std::size_t>(params.settle_tolerance_px);
      s_.stable_frames = steady ? s_.stable_frames + 1 : 0;
      settled = changed && s_.stable_frames >= params.settle_frames;
    }
    s_.previous_movable = movable;
    return settled;
  }

  // A keyframe was stored while the movable layer had `movable_px` pixels: the next movement is measured from it.
  void OnKeyframe(std::size_t movable_px) {
    s_.movable_at_keyframe = static_cast<std::int64_t>(movable_px);
    s_.reset_since_keyframe = 0;
    s_.stable_frames = 0;
  }

 private:
  SettleState s_;
};

}  // namespace anchordb::engine
