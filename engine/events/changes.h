#pragma once
// Change detection from keyframes (thesis 3.3.4 "Keyframes as memory references", 3.5.2): a keyframe is a raw
// depth snapshot plus the static background at that moment; applying a background to a depth image marks what
// stands in front of it (the movable test of Algorithm 1, theta = beta * background depth). Comparing the
// keyframes that open and close an action layer against the newer background gives what was added (in front of it
// at the end, not at the start) and what was removed (in front of it at the start, gone at the end).
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "engine/events/segments.h"
#include "schema/types.h"

namespace anchordb::engine {

struct ChangeParams {
  double beta = 0.03;           // theta(d) = beta * d, as Algorithm 1
  double min_theta_m = 0.015;   // never closer to the background than this (sensor noise near the camera)
  bool clean = true;            // the noise cleaning of the movable layer (CleanMovable) before clustering
  SegmentParams segments;
};

// 1 where depth is measured and nearer than the background (also measured) by more than theta.
std::vector<std::uint8_t> InFrontOfBackground(std::span<const std::uint16_t> depth_mm,
                                              std::span<const std::uint16_t> background_mm, const ChangeParams& p);

struct ChangeMasks {
  std::vector<std::uint8_t> added;    // in front of the background at the end, not (at that depth) at the start
  std::vector<std::uint8_t> removed;  // in front of the background at the start, gone at the end
};
// before/after: raw depth of the keyframes opening and closing the layer; background: the one at `after`.
ChangeMasks CompareKeyframes(std::span<const std::uint16_t> before_mm, std::span<const std::uint16_t> after_mm,
                             std::span<const std::uint16_t> background_mm, int width, int height, const ChangeParams& p);

// Points p_map of the mask's pixels.
std::vector<Eigen::Vector3f> MaskPoints(std::span<const std::uint8_t> mask, std::span<const std::uint16_t> depth_mm,
                                        const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera);

// Segments of the pixels of `mask` (cleaned first when p.clean).
std::vector<Segment> SegmentMask(std::vector<std::uint8_t> mask, std::span<const std::uint16_t> depth_mm,
                                 const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera, const ChangeParams& p);

// What a depth image says about points known from earlier (an object's sample): projected into the camera, each
// point inside the image is confirmed (measured within theta), seen through (measured farther: the object is not
// there any more), hidden (measured nearer: something in front) or unmeasured.
struct Visibility {
  int outside = 0;
  int confirmed = 0;
  int seen_through = 0;
  int hidden = 0;
  int unmeasured = 0;
  int Inside() const { return confirmed + seen_through + hidden + unmeasured; }
};
Visibility CheckVisibility(const std::vector<Eigen::Vector3f>& points_map, std::span<const std::uint16_t> depth_mm,
                           const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera, const ChangeParams& p,
                           double max_range_m = 4.5);

// Depth [mm] of points p_map as the camera at X_MapCamera sees them, nearest wins (a z-buffer with 2x2 splats so a
// background rendered from a nearby viewpoint has no pinholes); 0 where no point falls.
std::vector<std::uint16_t> RenderDepthMm(const std::vector<Eigen::Vector3f>& points_map, const PinholeIntrinsics& K,
                                         const Eigen::Isometry3d& X_MapCamera);

// Whether a segment is the same object as one known at `centroid_m` with bounding box `extent_m`: centroids within
// max(tolerance, half the larger object's horizontal extent) and a similar size.
struct MatchParams {
  double centroid_tolerance_m = 0.06;
  double min_size_ratio = 0.35;  // smaller / larger of the two bounding-box volumes (a partly seen object is smaller)
};
double MatchDistance(const Segment& s, const Eigen::Vector3d& centroid_m, const Eigen::Vector3d& extent_m);
bool Matches(const Segment& s, const Eigen::Vector3d& centroid_m, const Eigen::Vector3d& extent_m, const MatchParams& p);

// Size similarity in [0, 1] of two bounding boxes (sorted side lengths compared pairwise: the geometric mean of the
// min/max ratios, so one very different side is enough to tell two objects apart),
// the cue the lost-key rule uses to tell whether an addition can be the removed object.
double SizeSimilarity(const Eigen::Vector3d& extent_a_m, const Eigen::Vector3d& extent_b_m);

}  // namespace anchordb::engine
