#pragma once
// What forgetting (SPEC 4.5) knows of an old event or keyframe when it decides whether it stays, and the answers:
// storage/forgetting.cc gathers the facts in SQL, the keep rules of engine/forgetting/keep_rules.h decide, and
// storage applies the answer and counts it in the report by its reason. Plain vocabulary shared by both layers.
namespace anchordb {

struct OldEventFacts {
  bool pinned = false;              // an operator pinned the event
  bool labelled = false;            // a 'labelled' event: it names an instance (and proves no position)
  bool instance_pinned = false;     // the instance it concerns is pinned
  bool latest_of_instance = false;  // the newest event placing its instance (greatest stamp, then id)
};

// Why an old event stays, the first reason that holds; kForget: none does.
enum class EventKeep { kForget, kPinned, kLabelled, kInstancePinned, kLatestOfInstance };

struct OldKeyframeFacts {
  bool pinned = false;
  double relevance = 0.0;          // the keyframe's stored relevance, in [0, 1]
  bool referenced = false;         // an event's evidence, or the keyframe of a segment an event uses
  bool scene_open = false;         // its scene model is still observing
  bool scene_fed_recently = false; // ... and had a frame within the keyframe age
};

// Why an old keyframe stays, the first reason that holds; kForget: none does.
enum class KeyframeKeep { kForget, kPinned, kRelevant, kReferenced, kOpenScene };

}  // namespace anchordb
