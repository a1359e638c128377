#pragma once
// The footprint of a piece of furniture (thesis 5.3.1, SPEC §4.7-4.8): the rectangle its points cover on the floor,
// oriented along the principal axes of their horizontal spread, its height, and the overlap (IoU) of two
// footprints. Map frame M, z up, metres, radians.
#include <Eigen/Core>

#include <vector>

namespace anchordb::engine::segmentation {

struct Footprint {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  // centre of the rectangle in M [m]
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();  // full size along its own x (the major axis) and y [m]
  double yaw_rad = 0.0;                                 // rotation of its x axis from M's x, in [-pi/2, pi/2)
  double min_z_m = 0.0, max_z_m = 0.0;                  // lowest and highest point [m]
  double height_m() const { return max_z_m - min_z_m; }
};

// The footprint of `points_m`: its principal axes are the heading (1 deg steps) along which the points' horizontal
// coordinates pile up most (footprint.cc: a projection profile; for box-shaped furniture the directions of its
// faces, steadier than the axes of the points' covariance, which turn towards whichever face the camera saw most
// densely); its extents the range of the points along those axes, trimmed by the `trim` share of points at each end
// (flying pixels and stray noise). Empty input: a zero footprint.
Footprint FootprintOf(const std::vector<Eigen::Vector3f>& points_m, double trim = 0.01);

// A piece against a wall is seen from the front: its top and back are often hidden (the top at a grazing angle, the
// back by the piece itself). When one of the footprint's axes lies within `max_angle_rad` of the wall's horizontal
// normal (the wall: n . p + offset = 0 on the floor plane, n pointing into the room) and the footprint's nearest
// corner lies at most `reach_m` in front of the wall, the footprint is extended along that axis up to the wall.
Footprint ExtendToWall(const Footprint& f, const Eigen::Vector2d& normal, double offset, double reach_m, double max_angle_rad);

// Area of the intersection over the area of the union of two footprints (rotated rectangles; OpenCV's
// rotatedRectangleIntersection). 0 when either is degenerate (zero area).
double FootprintIoU(const Footprint& a, const Footprint& b);

// The share of a's area that lies inside b (0 when a is degenerate).
double FootprintOverlap(const Footprint& a, const Footprint& b);

// The four corners of the rectangle, counter-clockwise.
std::vector<Eigen::Vector2d> FootprintCorners(const Footprint& f);

}  // namespace anchordb::engine::segmentation
