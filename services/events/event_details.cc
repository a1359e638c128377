// The details of change events between the store's record and the service's view (see event_details.h).
#include "services/events/event_details.h"

namespace anchordb::services {

namespace {

std::array<double, 3> Stored(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d Vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

}  // namespace

storage::EventDetailsRecord StoredEventDetails(const EventDetails& d) {
  storage::EventDetailsRecord r;
  if (d.segment) r.segment = storage::EventSegmentDetails{Stored(d.segment->centroid_m), Stored(d.segment->extent_m), d.segment->points};
  if (d.move) r.move = storage::EventMoveDetails{Stored(d.move->from_m), d.move->size_similarity, d.move->removal_event};
  if (d.visibility) {
    const engine::Visibility& v = *d.visibility;
    r.visibility = storage::EventVisibilityDetails{v.outside, v.confirmed, v.seen_through, v.hidden, v.unmeasured};
  }
  r.background_scene = d.background_scene;
  r.label_weights = d.labels;
  return r;
}

EventDetails EventDetailsOf(const storage::EventDetailsRecord& r) {
  EventDetails d;
  if (r.segment) d.segment = engine::SegmentSummary{Vec3(r.segment->centroid_m), Vec3(r.segment->extent_m), r.segment->points};
  if (r.move) d.move = MoveEvidence{Vec3(r.move->from_m), r.move->size_similarity, r.move->removal_event};
  if (r.visibility) {
    const storage::EventVisibilityDetails& v = *r.visibility;
    d.visibility = engine::Visibility{static_cast<int>(v.outside), static_cast<int>(v.confirmed),
                                      static_cast<int>(v.seen_through), static_cast<int>(v.hidden),
                                      static_cast<int>(v.unmeasured)};
  }
  d.background_scene = r.background_scene;
  d.labels = r.label_weights;
  return d;
}

std::int64_t InsertLabelledEvent(storage::Connection& c, const std::string& map, std::int64_t instance,
                                 const std::string& label, const std::string& detection, std::int64_t stamp_ns,
                                 const std::string& explanation, const engine::LabelWeights& distribution) {
  storage::EventRecord e;
  e.map_id = map;
  e.type = "labelled";
  e.detection = detection;
  e.stamp_ns = stamp_ns;
  e.created_ns = stamp_ns;
  e.instance_id = instance;
  e.label = label;
  e.explanation = explanation;
  EventDetails details;
  details.labels = distribution;
  e.details = StoredEventDetails(details);
  return storage::InsertEvent(c, e);
}

}  // namespace anchordb::services
