#include "services/events/event_settings.h"

namespace anchordb::services {

void BindEventSettings(SettingsBinder& b, EventSettings& e) {
  auto& seg = e.change.segments;
  b.Bind("segment_cluster_tolerance_m", "Euclidean clustering of movable points: neighbour distance [m]",
         &seg.cluster_tolerance_m, 0.001, 1.0);
  b.Bind("segment_min_points", "smallest segment (movable pixels) that makes a change event", &seg.min_points, 1, 1e7);
  b.Bind("segment_min_extent_m", "smallest largest side of a segment's bounding box [m]", &seg.min_extent_m, 0.0, 10.0);
  b.Bind("event_min_theta_m", "a point is in front of the background by at least max(beta * depth, this) [m]",
         &e.change.min_theta_m, 0.0, 1.0);
  b.Bind("event_match_centroid_tolerance_m", "a segment is a known instance when their centroids are this close [m]",
         &e.match.centroid_tolerance_m, 0.0, 10.0);
  b.Bind("event_match_min_size_ratio", "... and the smaller bounding-box volume is at least this fraction of the larger",
         &e.match.min_size_ratio, 0.0, 1.0);
  b.Bind("event_move_min_size_similarity", "lost-key rule: an addition less similar in size than this to the removed "
         "labelled object is another object", &e.move_min_size_similarity, 0.0, 1.0);
  b.Bind("event_removed_min_seen_through", "fraction of an instance's visible points a later view sees through that "
         "makes it removed", &e.removed_min_seen_through, 0.0, 1.0);
  b.Bind("event_removed_min_visible_points", "fewer visible points of an instance prove nothing about its removal",
         &e.removed_min_visible_points, 1, 1e6);
}

}  // namespace anchordb::services
