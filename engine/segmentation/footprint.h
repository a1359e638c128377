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

// The footprint of `points_m` (at least one point): yaw from the principal axes of the horizontal coordinates
// (Eigen's self-adjoint eigen-solver on their covariance), extents from the points' range along those axes.
Footprint FootprintOf(const std::vector<Eigen::Vector3f>& points_m);

// Area of the intersection over the area of the union of two footprints (rotated rectangles; OpenCV's
// rotatedRectangleIntersection). 0 when either is degenerate (zero area).
double FootprintIoU(const Footprint& a, const Footprint& b);

// The four corners of the rectangle, counter-clockwise.
std::vector<Eigen::Vector2d> FootprintCorners(const Footprint& f);

}  // namespace anchordb::engine::segmentation
