#include "engine/forgetting/keep_rules.h"

namespace anchordb::engine::forgetting {

EventKeep KeepEvent(const OldEventFacts& event) {
  if (event.pinned) return EventKeep::kPinned;
  if (event.labelled) return EventKeep::kLabelled;
  if (event.instance_pinned) return EventKeep::kInstancePinned;
  if (event.latest_of_instance) return EventKeep::kLatestOfInstance;
  return EventKeep::kForget;
}

KeyframeKeep KeepKeyframe(const OldKeyframeFacts& keyframe, double keep_relevance_at_least) {
  if (keyframe.pinned) return KeyframeKeep::kPinned;
  if (keyframe.relevance >= keep_relevance_at_least) return KeyframeKeep::kRelevant;
  if (keyframe.referenced) return KeyframeKeep::kReferenced;
  if (keyframe.scene_open && keyframe.scene_fed_recently) return KeyframeKeep::kOpenScene;
  return KeyframeKeep::kForget;
}

}  // namespace anchordb::engine::forgetting
