#pragma once
// The keep rules of forgetting (SPEC 4.5): which old events and keyframes stay, and why. Each rule returns the first
// reason that holds, in the order of the enum (a pinned event is counted as pinned even when it is also labelled).
// storage/forgetting.cc asks them for every candidate older than the policy's age.
#include "schema/forgetting_facts.h"

namespace anchordb::engine::forgetting {

// Stays: pinned; a label (it names the instance); its instance is pinned; the newest event that places its instance
// (without it, where-is could no longer say where the thing was last seen).
EventKeep KeepEvent(const OldEventFacts& event);

// Stays: pinned; relevance at least `keep_relevance_at_least`; evidence of an event (directly or through a segment an
// event uses); of a scene still observing that had a frame within the keyframe age. A scene left observing longer
// (abandoned: its client never came back) protects nothing: its keyframes age like any others.
KeyframeKeep KeepKeyframe(const OldKeyframeFacts& keyframe, double keep_relevance_at_least);

}  // namespace anchordb::engine::forgetting
