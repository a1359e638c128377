#pragma once
// Change events, object instances over time and the lost-key question (thesis 3.3.4, 3.5.2, 1.4; SPEC §4.4).
//
// Every keyframe an observation stores is analysed here:
// - begin keyframe of a model that merged earlier ones (a later visit): what stands in front of the merged
//   background and matches no instance known to be present was added meanwhile; instances known to be present whose
//   points the new view now sees through were removed meanwhile;
// - every later keyframe (manual, settled, end) closes an action layer: comparing it with the keyframe that opened
//   the layer, against the newer background, gives what was added and removed while observing.
// Movable points are clustered in 3D (engine/events/segments.h) and matched to instances by position and size.
// Lost-key rule: an unlabelled addition observed after the removal of a labelled object, of compatible size, is that
// object, moved; the event says so and why. Operator edits (relabel, delete, pin) are locked against automatic
// processing.
#include <mutex>
#include <optional>

#include "services/furniture/furniture_service.h"
#include "services/scene/keyframe_listener.h"
#include "engine/events/changes.h"
#include "storage/event_repository.h"
#include "storage/store.h"
#include "services/common/transitional_json.h"

namespace anchordb::services {

struct EventSettings {
  engine::ChangeParams change;
  engine::MatchParams match;
  double move_min_size_similarity = 0.45;  // lost-key rule: a less similar addition is another object
  double removed_min_seen_through = 0.6;   // fraction of an instance's visible points seen through -> removed
  int removed_min_visible_points = 20;     // fewer visible points prove nothing
  std::size_t max_label_length = 64;
};

class EventService : public KeyframeListener {
 public:
  EventService(storage::Store& store, FurnitureService* furniture, EventSettings settings);

  Json OnKeyframe(const KeyframeNotice& notice) override;

  Json ListEvents(const std::string& map, const storage::EventFilter& filter);
  Json GetEvent(const std::string& map, std::int64_t id);
  Json LabelEvent(const std::string& map, std::int64_t id, const Json& body);

  Json CreateInstance(const std::string& map, const Json& body);  // operator-entered furniture or objects
  Json ListInstances(const std::string& map, const std::optional<std::string>& label, const storage::InstanceFilter& f);
  Json GetInstance(const std::string& map, std::int64_t id);
  Json History(const std::string& map, std::int64_t id);
  Json LabelInstance(const std::string& map, std::int64_t id, const Json& body);
  Json PinInstance(const std::string& map, std::int64_t id, bool pinned);
  Json DeleteInstance(const std::string& map, std::int64_t id);

  // at_ns: the state at that time (nullopt: now).
  Json Where(const std::string& map, const std::string& label, std::optional<std::int64_t> at_ns);

  Json PinKeyframe(const std::string& map, std::int64_t id, bool pinned);
  Json SetKeyframeRelevance(const std::string& map, std::int64_t id, const Json& body);
  // Applies a newer scene model's background to an old keyframe's raw depth (3.3.4): objects missed then.
  Json Reanalyse(const std::string& map, std::int64_t keyframe_id, const Json& body);

 private:
  Json AnalyseBegin(storage::Connection& c, const KeyframeNotice& n);
  Json AnalyseLayer(storage::Connection& c, const KeyframeNotice& n);
  Json AddedObject(storage::Connection& c, const std::string& map, const engine::Segment& s, std::int64_t segment_id,
                   const std::string& detection, std::int64_t stamp_ns, std::optional<std::int64_t> scene,
                   std::optional<std::int64_t> layer, std::vector<storage::EvidenceRecord> evidence);
  Json InstanceJson(const storage::InstanceRecord& r) const;
  Json EventJson(const storage::EventRecord& e) const;

  storage::Store& store_;
  FurnitureService* furniture_;
  EventSettings settings_;
  std::mutex analysis_mutex_;  // keyframe analyses of one server run one at a time (instances are shared state)
};

}  // namespace anchordb::services
