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
  b.Bind("where_cache_entries", "where-is questions for now (map and label) whose stored inputs are kept while their "
         "map's objects, labels and furniture graphs are unchanged; 0 keeps none", &e.where_cache_entries, 0, 1000000);
  b.Bind("stream_max_streams", "live event streams (events:stream) open at once; each holds an HTTP worker",
         &e.stream.max_streams, 1, 1000);
  b.Bind("stream_max_duration_s", "one events:stream response ends after this; the client resumes with Last-Event-ID [s]",
         &e.stream.max_duration_s, 1.0, 3600.0);
  b.Bind("stream_resume_jobs_s", "a resumed events:stream (Last-Event-ID or after=) first sends the map's jobs that "
         "ended within this window, so an end that happened while the client reconnected is not lost [s]",
         &e.stream.resume_jobs_s, 0.0, 86400.0);
  b.Bind("stream_poll_s", "how often an open events:stream looks for new events and job progress [s]", &e.stream.poll_s,
         0.01, 10.0);
}

void BindAnalysisQueueSettings(SettingsBinder& b, AnalysisQueueSettings& a) {
  b.Bind("analysis_threads", "worker threads running queued keyframe change analyses (one map's in keyframe order), "
                             "and as many catch-up workers at the requests' priority for maps analysis_catch_up_at behind",
         &a.threads, 0, 64);
  b.Bind("analysis_wait_max_s", "longest a request with wait_for_analysis=true waits for its keyframe's analysis [s]",
         &a.wait_max_s, 0.0, 3600.0);
  b.Bind("analysis_retry_initial_s", "backoff after a keyframe analysis' first failed attempt, doubling [s]",
         &a.retry_initial_s, 0.001, 3600.0);
  b.Bind("analysis_retry_max_s", "longest backoff between attempts of a failing keyframe analysis [s]", &a.retry_max_s,
         0.001, 86400.0);
  b.Bind("analysis_nice", "CPU niceness of the analysis workers (0: as the request threads; higher: requests go first)",
         &a.nice, 0, 19);
  b.Bind("analysis_catch_up_at", "pending keyframe analyses of a map from which they run at the requests' CPU priority "
                                 "(0: never)", &a.backlog.catch_up_at, 0, 1000000);
  b.Bind("analysis_max_pending", "pending keyframe analyses of a map from which its new frames and manual keyframes are "
                                 "refused with 503 and Retry-After until they catch up (0: never)",
         &a.backlog.max_pending, 0, 1000000);
  b.Bind("analysis_max_attempts", "attempts before a keyframe analysis failing with a non-transient error is given up",
         &a.max_attempts, 1, 1000000);
}

}  // namespace anchordb::services
