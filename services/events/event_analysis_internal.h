#pragma once
// Internal to services/events: what a keyframe analysis or a re-analysis reads from the store, how the write
// transaction re-checks it, and how a change set (engine/events/change_set.h) is written.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/events/change_set.h"
#include "engine/events/keyframe_analysis.h"
#include "services/scene/keyframe_listener.h"
#include "storage/event_repository.h"
#include "storage/scene_repository.h"
#include "storage/connection.h"

namespace anchordb::services::events_internal {

// The memory a keyframe analysis depends on. Read once on a snapshot, then again inside the write transaction: the
// change set is written only if both reads agree.
struct AnalysisInputs {
  std::vector<storage::InstanceRecord> records;                   // present (with samples) and absent objects, id order
  std::vector<std::optional<storage::HistoryRecord>> last_history;  // per record: newest row (lost-key candidates)
  std::vector<std::optional<std::int64_t>> last_keyframe;          // per record: latest keyframe of its last scene (begin)
  std::vector<std::int64_t> before_keyframes;                     // begin: latest keyframe of each merged model
  std::optional<std::int64_t> opening_keyframe_id;                // later keyframes: the one that opened the layer
  std::int64_t instance_version = 0;                              // the map's count when these were read
};
AnalysisInputs ReadAnalysisInputs(storage::Connection& c, const KeyframeNotice& n);
// Whether `in`, read earlier, still holds (in the write transaction): the map's instance count is the same (no
// instance, label or history row changed) and so are the keyframes it read -- a few ids, not every object with its
// sample, which is what the count spares (issue 33).
bool InputsUnchanged(storage::Connection& c, const KeyframeNotice& n, const AnalysisInputs& in);
std::vector<engine::KnownInstance> KnownInstances(const AnalysisInputs& in);

// What re-analysing keyframe `keyframe` depends on: every object instance (deleted too) with its history row at the
// keyframe's time, and the latest keyframe of the newer model.
struct ReanalysisInputs {
  bool keyframe_exists = false;
  std::vector<storage::InstanceRecord> records;
  std::vector<std::optional<storage::HistoryRecord>> at_keyframe;
  std::optional<std::int64_t> background_keyframe_id;
};
ReanalysisInputs ReadReanalysisInputs(storage::Connection& c, const std::string& map, const storage::KeyframeRecord& keyframe,
                                      std::int64_t background_scene_id);
bool SameInputs(const ReanalysisInputs& a, const ReanalysisInputs& b);
std::vector<engine::InstanceAtTime> InstancesAtTime(const ReanalysisInputs& in);

// Writes the change set (segments, new instances, events, updates, history rows, in that order). `records`: the
// stored instances it may update, by id. Returns the created events as stored.
std::vector<EventView> WriteChangeSet(storage::Connection& c, const std::string& map, const engine::ChangeSet& changes,
                                      std::map<std::int64_t, storage::InstanceRecord> records, std::int64_t now_ns);

bool Empty(const engine::ChangeSet& changes);

}  // namespace anchordb::services::events_internal
