#pragma once
// Change events, object instances over time and the lost-key question (thesis 3.3.4, 3.5.2, 1.4; SPEC §4.4).
//
// Every keyframe an observation stores is analysed here, from the analysis queue (analysis_queue.h) (the rules are in engine/events/keyframe_analysis.h): a
// begin keyframe of a later visit finds what was added and removed meanwhile, every later keyframe what was added and
// removed in the action layer it closes, and an observed addition may continue a labelled removal (the lost-key
// rule). The heavy part (clustering, visibility) runs on a snapshot outside any write transaction; the short write
// that follows checks that what the analysis read still holds (the map's instance change count of migration 0028 and
// the few keyframe ids it read) and, if another writer changed it meanwhile, the analysis is computed again (a
// bounded number of times, then inside the write). Analyses of one map run one at a time; different maps
// concurrently. Operator edits (relabel, delete) are locked against automatic processing.
//
// Errors (anchordb::Error): kNotFound for a missing map, event, instance, keyframe or scene (field names it);
// kInvalidArgument / kUnprocessable for bad values; kConflict for edits an operator's decision forbids.
#include <functional>
#include <map>
#include <memory>
#include <array>
#include <atomic>
#include <mutex>
#include <optional>
#include <string>

#include "engine/events/changes.h"
#include "engine/events/rules.h"
#include "schema/clock.h"
#include "services/events/event_types.h"
#include "services/events/where_inputs_cache.h"
#include "services/scene/keyframe_listener.h"
#include "storage/store.h"

namespace anchordb::services {

class FurnitureService;

struct EventSettings {
  engine::ChangeParams change;
  engine::MatchParams match;
  double move_min_size_similarity = engine::kMoveMinSizeSimilarity;  // lost-key rule: a less similar addition is another object
  double removed_min_seen_through = engine::kRemovedMinSeenThrough;  // fraction of an instance's visible points seen through -> removed
  int removed_min_visible_points = engine::kRemovedMinVisiblePoints;  // fewer visible points prove nothing
  std::size_t max_label_length = 64;
  // where-is questions for now whose stored inputs are kept between changes of their map's objects
  // (services/events/where_inputs_cache.h); 0 keeps none.
  int where_cache_entries = 256;
  // The live stream GET /v1/maps/{map}/events:stream (api/stream_routes.h). Each open stream holds one HTTP worker,
  // so at most max_streams are open at once (one more: 503 + Retry-After) and each ends after max_duration_s (the
  // client reconnects with Last-Event-ID and misses nothing): streams never take the workers other clients need.
  struct Stream {
    int max_streams = 4;           // below the server's worker_threads
    double max_duration_s = 30.0;  // [s] one response; then the client reconnects
    double poll_s = 0.2;           // [s] how often an open stream looks for new events and job progress
    double heartbeat_s = 10.0;     // [s] a comment line when nothing happened (finds dead clients)
    int retry_ms = 500;            // [ms] the reconnection delay the stream tells EventSource clients
    // [s] a resumed stream (Last-Event-ID or after=) first sends the jobs of the map that ended within this window:
    // a job that ended while the client was reconnecting is not lost (job messages are states; one may repeat).
    double resume_jobs_s = 300.0;
  } stream;
};

class EventService {
 public:
  // `furniture` (may be null) places where-is answers against furniture graphs.
  EventService(storage::Store& store, FurnitureService* furniture, EventSettings settings,
               const Clock& clock = SystemClock::Instance());

  // Runs in each write transaction of an analysis before it writes; false: write nothing (the queued analysis is gone).
  using Claim = std::function<bool(storage::Connection&)>;
  // Analyses one stored keyframe (services/events/analysis_queue.h runs them in order) and writes its change set with
  // `claim` in one transaction. nullopt when the claim was refused (nothing written).
  std::optional<KeyframeAnalysis> AnalyseKeyframe(const KeyframeNotice& notice, const Claim& claim = {});

  EventPage ListEvents(const std::string& map, const EventQuery& query);
  // The map's newest event id (0 when it has none); unknown map: kNotFound.
  std::int64_t LatestEventId(const std::string& map);
  const EventSettings& settings() const { return settings_; }
  const WhereInputsCache& where_cache() const { return where_cache_; }
  EventView GetEvent(const std::string& map, std::int64_t id);
  // Labels the instance the event concerns (kUnprocessable when it concerns none).
  LabelResult LabelEvent(const std::string& map, std::int64_t event_id, const LabelRequest& request);
  // An operator removes a wrong event: its row and evidence links go (the keyframes stay, unpinned references gone,
  // so forgetting may later collect them); what it did to its instance (position history, labels) stays, with the
  // history entry no longer pointing at it. Returns the event as it was. kNotFound for an unknown map or event.
  EventView DeleteEvent(const std::string& map, std::int64_t event_id);

  InstanceView CreateInstance(const std::string& map, const CreateInstanceRequest& request);
  InstancePage ListInstances(const std::string& map, const InstanceQuery& query);
  InstanceView GetInstance(const std::string& map, std::int64_t id);
  InstanceHistory History(const std::string& map, std::int64_t id);
  // Dialog adds evidence for a label; an operator's label replaces the others and locks it (kConflict for dialog
  // afterwards, and for a deleted instance).
  LabelResult LabelInstance(const std::string& map, std::int64_t id, const LabelRequest& request);
  InstanceView PinInstance(const std::string& map, std::int64_t id, bool pinned);
  // Kept as a tombstone (status deleted) so its events stay consistent; never revived.
  InstanceView DeleteInstance(const std::string& map, std::int64_t id);

  WhereAnswer Where(const std::string& map, const WhereRequest& request);

  KeyframePinned PinKeyframe(const std::string& map, std::int64_t id, bool pinned);
  KeyframeRelevance SetKeyframeRelevance(const std::string& map, std::int64_t id, double relevance);
  // Applies a newer scene model's background to an old keyframe's raw depth (3.3.4): objects missed then.
  ReanalyseResult Reanalyse(const std::string& map, std::int64_t keyframe_id, const ReanalyseRequest& request);

  // Keyframe analyses computed inside their write transaction (the optimistic attempts were all overtaken by other
  // writers of the map's instances): while one runs, every other writer of the file waits.
  std::int64_t analyses_in_write() const { return analyses_in_write_.load(); }

  // Tests only: runs between an analysis' computation and its write transaction (map id as argument).
  void SetAnalysisHookForTesting(std::function<void(const std::string& map)> hook) { analysis_hook_ = std::move(hook); }

 private:
  std::mutex& MapMutex(const std::string& map);
  engine::EventRules Rules() const;
  std::optional<WherePlacement> GraphPlacement(const std::string& map, const Eigen::Vector3d& p_map,
                                               std::optional<std::int64_t> graph);
  // The stored inputs of a where-is answer: for now (no at_ns) from where_cache_ while the map's stamp is unchanged.
  storage::WhereInputs WhereInputsFor(const std::string& map, const std::string& label, std::optional<std::int64_t> at_ns);

  storage::Store& store_;
  FurnitureService* furniture_;
  EventSettings settings_;
  const Clock& clock_;
  WhereInputsCache where_cache_;
  std::function<void(const std::string&)> analysis_hook_;
  std::atomic<std::int64_t> analyses_in_write_{0};
  // Analyses of one map run one at a time (instances are shared state; edits such as labels do not take it: the
  // analysis re-checks the instances in its write); maps hash onto a fixed set of mutexes, so
  // analyses of different maps run concurrently (unless two maps share a stripe) and no request can grow the set.
  static constexpr std::size_t kMapStripes = 64;
  std::array<std::mutex, kMapStripes> map_mutexes_;
};

}  // namespace anchordb::services
