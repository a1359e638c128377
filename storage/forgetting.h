#pragma once
// Forgetting (thesis 3.3.4, SPEC §4.5): keeps the memory bounded without removing what a live reference needs.
//
// One run over one map, in ONE write transaction (dry runs roll it back):
// 1. superseded scene models (closed, superseder still stored) lose their state blobs (background, weight, labels;
//    state_version 0, forgotten_ns set): the superseder merged their information;
// 2. events older than event_max_age_s go unless pinned, 'labelled', the latest event of their instance (it proves
//    the current position) or of a pinned instance; their evidence rows cascade, instance history keeps the position;
// 3. keyframes older than keyframe_max_age_s go unless pinned, relevance >= keep_relevance_at_least, evidence of a
//    remaining event, the source of a segment a remaining event uses, or of a scene still observing that had a
//    frame within keyframe_max_age_s (one left open longer is abandoned: its keyframes age like others); their
//    segments that no event uses go first;
// 4. forgotten superseded models without any keyframe left are deleted (the R*Tree row goes by trigger).
// Features are not stored yet: nothing is de-duplicated (the report says so).
// The foreign keys (no cascade onto keyframes) make a bookkeeping mistake fail and roll back instead of dangling.
//
// vacuum (only when something was committed, never in a dry run): incremental_vacuum when the file is in
// auto_vacuum=INCREMENTAL mode, otherwise a one-time switch (auto_vacuum=INCREMENTAL; VACUUM) outside any
// transaction, then a WAL checkpoint (TRUNCATE) so the file shrinks on disk.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "schema/forgetting_facts.h"
#include "storage/forget_policy.h"
#include "storage/connection.h"

namespace anchordb::storage {

struct ForgetReport {
  std::string map_id;
  bool dry_run = false;
  std::int64_t now_ns = 0;
  ForgetPolicy policy;
  std::vector<std::int64_t> models_state_dropped;
  std::vector<std::int64_t> models_deleted;
  std::vector<std::int64_t> events_deleted;
  std::vector<std::int64_t> keyframes_deleted;
  std::vector<std::int64_t> segments_deleted;
  // Anchored features that went with the deleted keyframes, and exact repeats removed (same map, type, anchor and
  // descriptor as an older feature: left only when de-duplication on insert was switched off or loosened later).
  std::int64_t features_deleted = 0, features_deduplicated = 0;
  // Old keyframes / events that stayed, by the first reason that kept them.
  // keyframes_kept_open_scene: of a scene still observing that had a frame within the keyframe age. Keyframes of a
  // scene left observing for longer (abandoned: its client never came back) go like others; counted here:
  std::int64_t keyframes_kept_pinned = 0, keyframes_kept_relevant = 0, keyframes_kept_referenced = 0,
               keyframes_kept_open_scene = 0, keyframes_of_abandoned_scenes = 0;
  std::int64_t events_kept_pinned = 0, events_kept_labelled = 0, events_kept_latest = 0,
               events_kept_pinned_instance = 0;
  std::int64_t bytes_freed_estimate = 0;  // blob and text bytes of what went (not counting page overhead)
  std::int64_t page_size = 0;
  std::int64_t page_count_before = 0, freelist_before = 0;
  std::int64_t page_count_after = 0, freelist_after = 0;  // at the end of the (committed or rolled back) transaction
  bool committed = false;
  // Vacuum (when requested and not a dry run).
  std::string vacuum_mode;  // "", "incremental", "switched_to_incremental", "full_auto_vacuum", "skipped (dry run)"
  std::int64_t file_bytes_before = 0, file_bytes_after = 0;  // main file + WAL
  std::int64_t page_count_after_vacuum = 0, freelist_after_vacuum = 0;
  double seconds = 0.0;
};

// stage, fraction in [0, 1]. It may throw to abort the run: the transaction rolls back and the exception propagates.
using ForgetProgress = std::function<void(std::string_view stage, double fraction)>;
// Runs inside the transaction just before it commits (not in a dry run): lets a caller record the outcome atomically
// with the deletions (the job row).
using ForgetBeforeCommit = std::function<void(Connection& c, const ForgetReport& report)>;

// The keep rules a run asks for every event and keyframe older than the policy's ages: the caller passes
// engine/forgetting/keep_rules.h's KeepEvent and KeepKeyframe (storage gathers the facts and applies the answers).
struct ForgetRules {
  std::function<EventKeep(const OldEventFacts&)> event;
  std::function<KeyframeKeep(const OldKeyframeFacts&, double keep_relevance_at_least)> keyframe;
};

// `c` must not be inside a transaction (Forget opens BEGIN IMMEDIATE, and VACUUM needs none). Unknown map: kNotFound.
ForgetReport Forget(Connection& c, const std::string& map_id, const ForgetPolicy& policy, const ForgetRules& rules,
                    std::int64_t now_ns, bool dry_run, const ForgetProgress& progress = {},
                    const ForgetBeforeCommit& before_commit = {});

// Size of the database file plus its WAL, in bytes (0 for a missing file).
std::int64_t DatabaseFileBytes(const std::string& path);

}  // namespace anchordb::storage
