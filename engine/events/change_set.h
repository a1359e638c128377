#pragma once
// The outcome of analysing a keyframe (thesis 3.3.4, 3.5.2; SPEC §4.4) as plain data: the segments to keep, the
// instances to create or update, the change events to record and the history rows to append, in the order they are
// to be written. engine/events/keyframe_analysis.h computes it from typed inputs; the event service writes it in one
// short transaction. Positions are in the map frame [m], times in ns since the epoch.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/events/changes.h"
#include "engine/events/labels.h"
#include "engine/events/segments.h"

namespace anchordb::engine {

// A row that exists (id) or one this change set creates (index into its list of new instances or events).
struct Ref {
  std::int64_t id = 0;
  int new_index = -1;
  static Ref Existing(std::int64_t id) { return {id, -1}; }
  static Ref New(std::size_t index) { return {0, static_cast<int>(index)}; }
  bool is_new() const { return new_index >= 0; }
  bool operator==(const Ref&) const = default;
};

// One row of an instance's position history.
struct HistoryPoint {
  std::int64_t stamp_ns = 0;
  bool present = true;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  std::optional<Ref> event;  // the event that put it there, if any
};

// An object instance of the map as the analysis sees it.
struct KnownInstance {
  std::int64_t id = 0;
  bool present = true;                 // else absent (deleted instances are not known to the analysis)
  bool status_locked = false;          // an operator's decision: never changed automatically
  LabelWeights labels;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();  // axis-aligned bounding box
  std::vector<Eigen::Vector3f> sample_m;               // present objects: points as last seen, for visibility
  std::int64_t last_seen_ns = 0;
  std::optional<std::int64_t> last_keyframe_id;        // the latest keyframe of the scene that saw it last
  std::optional<HistoryPoint> last_history;            // absent labelled objects: the newest history row
};

struct SegmentSummary {
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();
  std::int64_t points = 0;
};
SegmentSummary Summarise(const Segment& s);

enum class EventType { kAdded, kRemoved, kMoved };
enum class Detection { kObserved, kMeanwhile, kReanalysis };
const char* EventTypeName(EventType type);   // added | removed | moved
const char* DetectionName(Detection detection);  // observed | meanwhile | reanalysis

struct Evidence {
  std::int64_t keyframe_id = 0;
  std::string role;  // before | after
  bool operator==(const Evidence&) const = default;
};

// Why a move was inferred (the lost-key rule).
struct MoveDetails {
  Eigen::Vector3d from_m = Eigen::Vector3d::Zero();  // where the removal left it
  double size_similarity = 0.0;
  std::optional<Ref> removal_event;
};

struct NewEvent {
  EventType type = EventType::kAdded;
  Detection detection = Detection::kObserved;
  std::int64_t stamp_ns = 0;
  std::optional<std::int64_t> scene_id;
  std::optional<std::int64_t> action_layer;
  Ref instance;
  std::optional<int> segment;          // index into ChangeSet::segments
  std::optional<std::string> label;
  std::string explanation;
  std::vector<Evidence> evidence;
  // Details, as far as they apply.
  std::optional<SegmentSummary> segment_summary;
  std::optional<Visibility> visibility;
  std::optional<MoveDetails> move;
  std::optional<std::int64_t> background_scene;
};

struct SegmentToStore {
  std::int64_t keyframe_id = 0;  // the keyframe whose depth shows it
  Segment segment;
};

struct NewInstance {  // an object (unlabelled)
  bool present = false;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> sample_m;
  std::int64_t last_seen_ns = 0;
  std::optional<std::int64_t> last_scene_id;
};

// Fields to change on an existing instance; unset fields keep their value. `touch`: its update time becomes now.
struct InstanceUpdate {
  Ref instance;
  std::optional<bool> present;
  std::optional<Eigen::Vector3d> position_m;
  std::optional<Eigen::Vector3d> extent_m;
  std::optional<std::int64_t> last_seen_ns;
  std::optional<std::int64_t> last_scene_id;
  std::optional<std::vector<Eigen::Vector3f>> sample_m;
  bool touch = false;
};

struct HistoryRow {
  Ref instance;
  std::int64_t stamp_ns = 0;
  bool present = true;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  std::optional<Ref> event;
};

// Written in this order: segments, new instances, events, updates (in order; one instance may be updated more than
// once), history rows (in order).
struct ChangeSet {
  std::vector<SegmentToStore> segments;
  std::vector<NewInstance> new_instances;
  std::vector<NewEvent> events;
  std::vector<InstanceUpdate> updates;
  std::vector<HistoryRow> history;
  int segments_examined = 0;  // every segment the analysis judged, matched or not
};

}  // namespace anchordb::engine
