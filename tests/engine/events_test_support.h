#pragma once
// Constructed segments and instances for the engine tests of the event rules (map frame, metres).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/events/change_set.h"
#include "engine/events/keyframe_analysis.h"

namespace anchordb::engine::testing {

// A box-shaped segment centred at c with side lengths e; `sample_points` points on its front face (z = min z).
inline Segment Box(const Eigen::Vector3d& c, const Eigen::Vector3d& e, int points = 500, int sample_points = 0) {
  Segment s;
  s.centroid_m = c;
  s.min_m = c - 0.5 * e;
  s.max_m = c + 0.5 * e;
  s.points = points;
  for (int i = 0; i < sample_points; ++i) {
    const double u = (i % 10) / 9.0 - 0.5, v = (i / 10 % 10) / 9.0 - 0.5;
    s.sample_m.emplace_back(static_cast<float>(c.x() + u * e.x()), static_cast<float>(c.y() + v * e.y()), static_cast<float>(s.min_m.z()));
  }
  return s;
}

inline KnownInstance Instance(std::int64_t id, bool present, const Eigen::Vector3d& position_m, const Eigen::Vector3d& extent_m) {
  KnownInstance k;
  k.id = id;
  k.present = present;
  k.position_m = position_m;
  k.extent_m = extent_m;
  return k;
}

// An absent instance named `label`, last seen at position_m and taken away at `removed_ns`.
inline KnownInstance Removed(std::int64_t id, const std::string& label, const Eigen::Vector3d& position_m,
                             const Eigen::Vector3d& extent_m, std::int64_t removed_ns, std::int64_t removal_event = 0) {
  KnownInstance k = Instance(id, false, position_m, extent_m);
  k.labels = {{label, 1.0}};
  k.last_history = HistoryPoint{removed_ns, false, position_m, removal_event ? std::optional(Ref::Existing(removal_event)) : std::nullopt};
  return k;
}

// A keyframe `keyframe_id` of scene `scene_id` closing the action layer that keyframe `opening_id` opened.
inline LayerKeyframe Layer(std::int64_t keyframe_id, std::int64_t opening_id, std::int64_t stamp_ns, std::int64_t opening_stamp_ns,
                           std::int64_t scene_id = 0, std::int64_t action_layer = 0) {
  LayerKeyframe k;
  k.keyframe_id = keyframe_id;
  k.scene_id = scene_id;
  k.stamp_ns = stamp_ns;
  k.opening_keyframe_id = opening_id;
  k.opening_stamp_ns = opening_stamp_ns;
  k.action_layer = action_layer;
  return k;
}

}  // namespace anchordb::engine::testing
