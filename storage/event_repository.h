#pragma once
// SQL for segments, object instances with their position history, change events with their evidence keyframes,
// and jobs (migration 0004).
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct SegmentRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::int64_t keyframe_id = 0;
  double centroid[3] = {0, 0, 0};
  double min[3] = {0, 0, 0};
  double max[3] = {0, 0, 0};
  std::int64_t points = 0;
  std::string sample;  // blob f32 {n, 3}
};
std::int64_t InsertSegment(Connection& c, const SegmentRecord& s);
std::optional<SegmentRecord> FindSegment(Connection& c, std::int64_t id);

struct InstanceRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::string kind = "object";
  std::string status = "present";
  // The labels people gave (dialog, operator) or a furniture category's p(f): label -> weight, rows of
  // instance_labels (migration 0026) written with the instance.
  std::map<std::string, double> labels;
  bool label_locked = false;
  bool status_locked = false;
  bool pinned = false;
  double position[3] = {0, 0, 0};
  double extent[3] = {0, 0, 0};
  double yaw_rad = 0.0;
  std::string sample;  // blob, may be empty
  std::int64_t last_seen_ns = 0;
  std::optional<std::int64_t> last_scene_id;
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
};
std::int64_t InsertInstance(Connection& c, const InstanceRecord& r);
void UpdateInstance(Connection& c, const InstanceRecord& r);  // every column and the labels, but id, map_id, created_ns
std::optional<InstanceRecord> FindInstance(Connection& c, const std::string& map_id, std::int64_t id, bool with_sample);
struct InstanceFilter {
  std::optional<std::string> kind;
  std::optional<std::string> status;      // exact; default: everything but 'deleted'
  bool include_deleted = false;
  std::optional<std::string> label;       // only instances whose label distribution has this label
  // With `label`: also an instance nobody named (no dialog or operator label) whose stored classification
  // (instance_classifications) gives `label` a share > 0, except the rejection class "unknown": the labels such an
  // instance shows (engine/classification/object_labels.h EffectiveObjectLabels).
  bool label_from_classifier = false;
  std::int64_t after_id = 0;
  int limit = 100;
};
std::vector<InstanceRecord> ListInstances(Connection& c, const std::string& map_id, const InstanceFilter& f,
                                          bool with_sample);

// The map's count of changes to its instances, their labels and history rows (migration 0028; 0 before the first):
// equal counts at two times mean none of those rows changed in between.
std::int64_t InstanceVersion(Connection& c, const std::string& map_id);

struct HistoryRecord {
  std::int64_t instance_id = 0;
  std::int64_t seq = 0;
  std::int64_t stamp_ns = 0;
  bool present = true;
  double position[3] = {0, 0, 0};
  std::optional<std::int64_t> event_id;
};
void AppendHistory(Connection& c, const HistoryRecord& h);  // seq assigned: last + 1
std::vector<HistoryRecord> ListHistory(Connection& c, std::int64_t instance_id);
// The last history entry at or before `at_ns`.
std::optional<HistoryRecord> HistoryAt(Connection& c, std::int64_t instance_id, std::int64_t at_ns);

// What "where is <label>?" reads first, in one statement (one round trip on PostgreSQL, no transaction needed):
// the map's objects a person labelled `label` (not deleted, by id) with their history entry at or before `at_ns`,
// the map's furniture instances (not deleted, by id, at most 10,000), and the id of its newest furniture graph.
struct WhereCandidateRecord {
  InstanceRecord instance;
  std::optional<HistoryRecord> position;
};
// What those inputs depend on besides the label and the time: the map (its creation time: a map deleted and made
// again under the same id is another map), its count of instance changes (InstanceVersion) and its newest furniture
// graph. Inputs read with a stamp are still the inputs while the map's stamp is equal to it.
struct WhereStamp {
  std::optional<std::int64_t> map_created_ns;  // absent: no such map
  std::int64_t instance_version = 0;
  std::optional<std::int64_t> newest_graph_id;
  bool operator==(const WhereStamp&) const = default;
};
// The map's stamp now, in one statement (three index lookups).
WhereStamp ReadWhereStamp(Connection& c, const std::string& map_id);
struct WhereInputs {
  std::vector<WhereCandidateRecord> labelled;
  std::vector<InstanceRecord> furniture;
  WhereStamp stamp;  // read by the same statement (one snapshot); holds the newest graph id
};
WhereInputs ReadWhereInputs(Connection& c, const std::string& map_id, const std::string& label, std::int64_t at_ns);

struct EvidenceRecord {
  std::int64_t keyframe_id = 0;
  std::string role;  // before | after
};
// The details of a change event (migration 0020: typed columns of the events row and event_label_weights), each
// part present when it applies.
struct EventSegmentDetails {  // the segment that showed the change
  std::array<double, 3> centroid_m{};
  std::array<double, 3> extent_m{};
  std::int64_t points = 0;
};
struct EventMoveDetails {  // an inferred move
  std::array<double, 3> from_m{};
  double size_similarity = 0.0;
  std::optional<std::int64_t> removal_event;
};
struct EventVisibilityDetails {  // a removal seen through: pixels of the segment by outcome
  std::int64_t outside = 0;
  std::int64_t confirmed = 0;
  std::int64_t seen_through = 0;
  std::int64_t hidden = 0;
  std::int64_t unmeasured = 0;
};
struct EventDetailsRecord {
  std::optional<EventSegmentDetails> segment;
  std::optional<EventMoveDetails> move;
  std::optional<EventVisibilityDetails> visibility;
  std::optional<std::int64_t> background_scene;               // re-analysis: the newer model whose background was applied
  std::optional<std::map<std::string, double>> label_weights;  // a label event: the distribution after it
};

struct EventRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::string type;
  std::string detection;
  std::int64_t stamp_ns = 0;
  std::optional<std::int64_t> scene_id;
  std::optional<std::int64_t> action_layer;
  std::optional<std::int64_t> instance_id;
  std::optional<std::int64_t> segment_id;
  std::optional<std::string> label;
  std::string explanation;
  EventDetailsRecord details;
  bool pinned = false;
  std::int64_t created_ns = 0;
  std::vector<EvidenceRecord> evidence;
};
std::int64_t InsertEvent(Connection& c, const EventRecord& e);  // with its evidence
std::optional<EventRecord> FindEvent(Connection& c, const std::string& map_id, std::int64_t id);
struct EventFilter {
  std::optional<std::int64_t> since_ns;
  std::optional<std::int64_t> until_ns;
  std::optional<std::string> type;
  std::optional<std::int64_t> instance_id;
  std::optional<std::int64_t> scene_id;
  std::int64_t after_id = 0;
  int limit = 100;
};
// Events in (stamp_ns, id) order.
std::vector<EventRecord> ListEvents(Connection& c, const std::string& map_id, const EventFilter& f);
// The newest event id of the map (0 when it has none): where a live stream without Last-Event-ID starts.
std::int64_t MaxEventId(Connection& c, const std::string& map_id);
void SetEventInstance(Connection& c, std::int64_t event_id, std::int64_t instance_id);
// Deletes one event of the map with its evidence rows (instance_history.event_id of entries it caused becomes NULL);
// false when the map has no such event.
bool DeleteEvent(Connection& c, const std::string& map_id, std::int64_t event_id);

// Keyframes: the latest of a scene (before `before_id` when given), pinning and relevance.
std::optional<std::int64_t> LatestKeyframeId(Connection& c, std::int64_t scene_id);
// The keyframe of the scene stored just before `keyframe_id` (the one that opened its action layer).
std::optional<std::int64_t> PreviousKeyframeId(Connection& c, std::int64_t scene_id, std::int64_t keyframe_id);
bool SetKeyframePinned(Connection& c, const std::string& map_id, std::int64_t id, bool pinned);
bool SetKeyframeRelevance(Connection& c, const std::string& map_id, std::int64_t id, double relevance);
// How many events use the keyframe as evidence and how many segments came from it.
std::int64_t KeyframeReferences(Connection& c, std::int64_t id);

}  // namespace anchordb::storage
