// A journalled frame's model-after between the journal row's typed columns and the engine's counts and settle state
// (see scene_stored_documents.h).
#include <limits>

#include "schema/error.h"
#include "services/scene/scene_stored_documents.h"

namespace anchordb::services::scene_stored {

storage::JournalModelAfter EncodeModelAfter(const engine::FrameCounts& c, const engine::SettleState& s) {
  const auto px = [](std::size_t n) { return static_cast<std::int64_t>(n); };
  return {px(c.supported),           px(c.reset),          px(c.movable),
          px(c.dynamic),             px(c.no_depth),       s.movable_at_keyframe,
          s.reset_since_keyframe,    s.previous_movable,   std::int64_t{s.stable_frames}};
}

ModelAfter DecodeModelAfter(const storage::JournalModelAfter& a, std::int64_t scene_id, std::int64_t frame) {
  const auto fail = [&](const char* what) {
    return Error(ErrorCode::kInternal, "journalled frame " + std::to_string(frame) + " of scene " +
                                           std::to_string(scene_id) + " has an unreadable model_after: " + what);
  };
  for (const std::int64_t n : {a.supported_px, a.reset_px, a.movable_px, a.dynamic_px, a.no_depth_px,
                               a.settle_movable_at_keyframe_px, a.settle_reset_since_keyframe_px}) {
    if (n < 0) throw fail("a negative pixel count");
  }
  if (a.settle_previous_movable_px < -1) throw fail("a previous movable count below -1");
  if (a.settle_stable_frames < 0 || a.settle_stable_frames > std::numeric_limits<int>::max()) {
    throw fail("a stable frame count out of range");
  }
  ModelAfter out;
  out.counts.supported = static_cast<std::size_t>(a.supported_px);
  out.counts.reset = static_cast<std::size_t>(a.reset_px);
  out.counts.movable = static_cast<std::size_t>(a.movable_px);
  out.counts.dynamic = static_cast<std::size_t>(a.dynamic_px);
  out.counts.no_depth = static_cast<std::size_t>(a.no_depth_px);
  out.settle.movable_at_keyframe = a.settle_movable_at_keyframe_px;
  out.settle.reset_since_keyframe = a.settle_reset_since_keyframe_px;
  out.settle.previous_movable = a.settle_previous_movable_px;
  out.settle.stable_frames = static_cast<int>(a.settle_stable_frames);
  return out;
}

}  // namespace anchordb::services::scene_stored
