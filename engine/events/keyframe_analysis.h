#pragma once
// What a stored keyframe changes in the memory of objects (thesis 3.3.4, 3.5.2; SPEC §4.4), as a ChangeSet computed
// from typed inputs; no storage, no clock. The segments (engine/events/changes.h SegmentMask) are computed by the
// caller first, since they do not depend on what the memory knows.
// - begin keyframe of a model that merged earlier ones (a later visit): a segment in front of the merged background
//   that is no instance known to be present was added meanwhile; a present instance whose sample points the view now
//   sees through was removed meanwhile;
// - a later keyframe closes an action layer: segments removed and added between the keyframe that opened it and this
//   one, against the newer background, are removals and additions observed (removals first); an observed addition
//   may continue a labelled removal (the lost-key rule, rules.h).
// - re-analysis of an old keyframe with a newer background: segments that were part of the background then and that
//   no instance explains were there then and are gone now.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "engine/events/change_set.h"
#include "engine/events/rules.h"
#include "schema/types.h"

namespace anchordb::engine {

struct BeginKeyframe {
  std::int64_t keyframe_id = 0;
  std::int64_t scene_id = 0;
  std::int64_t stamp_ns = 0;
  std::vector<std::int64_t> before_keyframes;  // the latest keyframe of each merged model (evidence "before")
  std::vector<Segment> front_segments;         // in front of the merged background; empty when nothing was merged
  // This keyframe's raw depth and camera, for the visibility of instances believed present.
  std::span<const std::uint16_t> depth_mm;
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
  ChangeParams change;
};
// `instances`: the map's objects that are present or absent, in id order.
ChangeSet AnalyseBeginKeyframe(const BeginKeyframe& k, const std::vector<KnownInstance>& instances, const EventRules& rules);

struct LayerKeyframe {
  std::int64_t keyframe_id = 0;
  std::int64_t scene_id = 0;
  std::int64_t stamp_ns = 0;
  std::int64_t opening_keyframe_id = 0;   // the keyframe that opened the action layer
  std::int64_t opening_stamp_ns = 0;
  std::int64_t action_layer = 0;          // the layer it opened
  std::vector<Segment> removed_segments;  // of the opening keyframe's depth
  std::vector<Segment> added_segments;    // of this keyframe's depth
};
ChangeSet AnalyseLayerKeyframe(const LayerKeyframe& k, const std::vector<KnownInstance>& instances, const EventRules& rules);

struct ReanalysedKeyframe {
  std::int64_t keyframe_id = 0;
  std::int64_t scene_id = 0;
  std::int64_t stamp_ns = 0;
  std::int64_t action_layer = 0;
  std::int64_t background_scene_id = 0;                // the newer model whose background was applied
  std::int64_t background_stamp_ns = 0;                // its last frame
  std::optional<std::int64_t> background_keyframe_id;  // its latest keyframe
  std::vector<Segment> segments;                       // in front of the newer background
};
// An object instance (any status) and its history row at the keyframe's time.
struct InstanceAtTime {
  std::int64_t id = 0;
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();
  std::optional<HistoryPoint> at_keyframe;
};
struct Reanalysis {
  ChangeSet changes;
  std::vector<std::optional<std::int64_t>> known_instance;  // per segment: the instance that explains it
};
Reanalysis ReanalyseKeyframe(const ReanalysedKeyframe& k, const std::vector<InstanceAtTime>& instances, const MatchParams& match);

}  // namespace anchordb::engine
