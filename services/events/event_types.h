#pragma once
// Typed requests and results of the event service (SPEC §4.4, §5): change events, object instances over time, the
// where-is answer and keyframe operations. Positions are in the map frame [m]; times are ns since the Unix epoch.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/events/change_set.h"
#include "engine/events/labels.h"
#include "storage/event_repository.h"

namespace anchordb::services {

// --- Change events ---------------------------------------------------------------------------------------------

// Why an event was inferred (the lost-key rule): where the removal left the object, the size similarity, and the
// removal event (null when forgetting removed it).
struct MoveEvidence {
  Eigen::Vector3d from_m = Eigen::Vector3d::Zero();
  double size_similarity = 0.0;
  std::optional<std::int64_t> removal_event;
};

// What an event records beyond its columns, as far as it applies to the event's kind.
struct EventDetails {
  std::optional<engine::SegmentSummary> segment;     // the segment that showed the change
  std::optional<engine::Visibility> visibility;      // a removal seen through (begin keyframe of a later visit)
  std::optional<MoveEvidence> move;                  // an inferred move
  std::optional<std::int64_t> background_scene;      // re-analysis: the newer model whose background was applied
  std::optional<engine::LabelWeights> labels;        // a label event: the distribution after it
};

struct EvidenceKeyframe {
  std::int64_t keyframe_id = 0;
  std::string role;  // before | after
};

struct EventView {
  std::int64_t id = 0;
  std::string type;       // added | removed | moved | labelled
  std::string detection;  // observed | meanwhile | reanalysis | dialog | operator
  std::int64_t stamp_ns = 0;
  std::optional<std::int64_t> scene_id;
  std::optional<std::int64_t> action_layer;
  std::optional<std::int64_t> instance_id;
  std::optional<std::int64_t> segment_id;
  std::optional<std::string> label;
  std::string explanation;
  EventDetails details;
  std::vector<EvidenceKeyframe> evidence;
};

// since/until/type/instance/scene filters, after_id paging, limit in [1, 1000].
using EventQuery = storage::EventFilter;

struct EventPage {
  std::vector<EventView> events;
  std::optional<std::int64_t> next_after;  // set when the page is full: the id to continue after
};

// --- Instances -------------------------------------------------------------------------------------------------

// What a trained classifier made of an object instance's segment (POST .../instances/{id}:classify).
struct ObjectClassificationView {
  std::string classifier;
  std::string label;                 // the most probable class
  engine::LabelWeights distribution;  // every class of the classifier
  std::optional<std::int64_t> segment_id, keyframe_id;
  std::int64_t stamp_ns = 0;
};

struct InstanceView {
  std::int64_t id = 0;
  std::string kind;    // object | furniture
  std::string status;  // present | absent | deleted
  // The label distribution (sums to 1, or empty): dialog's or an operator's, else a classifier's
  // (engine/classification/object_labels.h); label_source says which (dialog | operator | classifier | none).
  engine::LabelWeights labels;
  std::string label_source = "none";
  std::optional<ObjectClassificationView> classification;  // the last classification, also when not the label
  bool label_locked = false;
  bool pinned = false;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  std::int64_t last_seen_ns = 0;
  std::optional<std::int64_t> last_scene_id;
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
};

struct InstanceQuery {
  std::optional<std::string> label;   // as a person said it (normalised by the service)
  std::optional<std::string> kind;    // object | furniture
  std::optional<std::string> status;  // present | absent | deleted (default: all but deleted)
  std::int64_t after_id = 0;
  int limit = 100;
};

struct InstancePage {
  std::vector<InstanceView> instances;
  std::optional<std::int64_t> next_after;
};

struct HistoryEntry {
  std::int64_t seq = 0;
  std::int64_t stamp_ns = 0;
  bool present = true;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  std::optional<std::int64_t> event_id;
};

struct InstanceHistory {
  InstanceView instance;
  std::vector<HistoryEntry> history;
};

enum class InstanceKind { kFurniture, kObject };

// An operator enters furniture (for where-is sentences) or an object by hand.
struct CreateInstanceRequest {
  InstanceKind kind = InstanceKind::kFurniture;
  std::string label;               // as given (normalised by the service)
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();  // must not be negative
  double yaw_rad = 0.0;
  std::optional<std::int64_t> stamp_ns;  // when it was there (default now)
};

enum class LabelSource { kDialog, kOperator };

struct LabelRequest {
  std::string label;  // as said (normalised by the service)
  LabelSource source = LabelSource::kDialog;
};

struct LabelResult {
  InstanceView instance;
  EventView event;                            // the 'labelled' event
  std::optional<std::int64_t> labelled_event;  // labelling through an event: that event
};

// --- Where is ... ? ----------------------------------------------------------------------------------------------

// The furniture a where-is answer places the object against: a piece of the map's newest furniture graph (graph,
// furniture, category set; frame null for "on"), or, without a graph, an instance of kind furniture an operator
// entered (furniture_instance set; frame "geometry").
struct WherePlacement {
  std::optional<std::int64_t> graph;
  std::string furniture;
  std::string category;
  std::optional<std::int64_t> furniture_instance;
  std::string name;       // what the robot calls the piece
  std::string relation;   // on | left_of | right_of | in_front_of | behind | ...
  std::optional<std::string> frame;
  double gap_m = 0.0;     // from the piece's footprint
  std::string phrase;     // "on the table"
};

struct WhereRequest {
  std::string label;               // as asked (normalised by the service)
  std::optional<std::int64_t> at_ns;  // the state at that time (nullopt: now); not in the future
};

struct WhereEvidence {
  std::int64_t keyframe_id = 0;
  std::string role;
  std::int64_t event_id = 0;
};

struct WhereAnswer {
  std::string label;
  std::int64_t instance_id = 0;
  bool present = true;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  std::int64_t seen_ns = 0;
  std::string how;  // observed | meanwhile | inferred | reanalysis | ...
  std::vector<WhereEvidence> evidence;
  double confidence = 0.0;
  double label_probability = 0.0;
  std::string label_source;  // dialog | operator (a person named it) | classifier (nobody named an instance so)
  std::optional<std::int64_t> at_ns;
  std::optional<WherePlacement> placement;
  std::string sentence;
};

// --- Keyframes ---------------------------------------------------------------------------------------------------

struct KeyframePinned {
  std::int64_t keyframe_id = 0;
  bool pinned = false;
};

struct KeyframeRelevance {
  std::int64_t keyframe_id = 0;
  double relevance = 0.0;  // in [0, 1]
};

struct ReanalyseRequest {
  std::optional<std::int64_t> scene_id;  // the newer model (default: the newest of the place with a background)
};

struct ReanalysedSegment {
  engine::SegmentSummary segment;
  std::optional<std::int64_t> known_instance;  // the instance that explains it, if any
};

struct ReanalyseResult {
  std::int64_t keyframe_id = 0;
  std::int64_t background_scene_id = 0;
  std::vector<ReanalysedSegment> segments;
  std::vector<EventView> events;
};

}  // namespace anchordb::services
