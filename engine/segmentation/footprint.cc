#include "engine/segmentation/footprint.h"

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace anchordb::engine::segmentation {

Footprint FootprintOf(const std::vector<Eigen::Vector3f>& points_m) {
  Footprint f;
  if (points_m.empty()) return f;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  f.min_z_m = std::numeric_limits<double>::infinity();
  f.max_z_m = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3f& p : points_m) {
    mean += p.head<2>().cast<double>();
    f.min_z_m = std::min(f.min_z_m, static_cast<double>(p.z()));
    f.max_z_m = std::max(f.max_z_m, static_cast<double>(p.z()));
  }
  mean /= static_cast<double>(points_m.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector3f& p : points_m) {
    const Eigen::Vector2d d = p.head<2>().cast<double>() - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Vector2d major = eig.eigenvectors().col(1);  // largest eigenvalue last
  double yaw = std::atan2(major.y(), major.x());
  if (yaw >= std::numbers::pi / 2) yaw -= std::numbers::pi;
  if (yaw < -std::numbers::pi / 2) yaw += std::numbers::pi;
  const Eigen::Vector2d ax(std::cos(yaw), std::sin(yaw)), ay(-std::sin(yaw), std::cos(yaw));
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (const Eigen::Vector3f& p : points_m) {
    const Eigen::Vector2d d = p.head<2>().cast<double>() - mean;
    lo_x = std::min(lo_x, d.dot(ax));
    hi_x = std::max(hi_x, d.dot(ax));
    lo_y = std::min(lo_y, d.dot(ay));
    hi_y = std::max(hi_y, d.dot(ay));
  }
  f.yaw_rad = yaw;
  f.extent_m = Eigen::Vector2d(hi_x - lo_x, hi_y - lo_y);
  f.centre_m = mean + ax * 0.5 * (lo_x + hi_x) + ay * 0.5 * (lo_y + hi_y);
  return f;
}

std::vector<Eigen::Vector2d> FootprintCorners(const Footprint& f) {
  const Eigen::Vector2d ax(std::cos(f.yaw_rad), std::sin(f.yaw_rad)), ay(-std::sin(f.yaw_rad), std::cos(f.yaw_rad));
  const Eigen::Vector2d hx = 0.5 * f.extent_m.x() * ax, hy = 0.5 * f.extent_m.y() * ay;
  return {f.centre_m - hx - hy, f.centre_m + hx - hy, f.centre_m + hx + hy, f.centre_m - hx + hy};
}

double FootprintIoU(const Footprint& a, const Footprint& b) {
  const double area_a = a.extent_m.prod(), area_b = b.extent_m.prod();
  if (!(area_a > 0.0) || !(area_b > 0.0)) return 0.0;
  const auto rect = [](const Footprint& f) {
    return cv::RotatedRect(cv::Point2f(static_cast<float>(f.centre_m.x()), static_cast<float>(f.centre_m.y())),
                           cv::Size2f(static_cast<float>(f.extent_m.x()), static_cast<float>(f.extent_m.y())),
                           static_cast<float>(f.yaw_rad * 180.0 / std::numbers::pi));
  };
  std::vector<cv::Point2f> region;
  if (cv::rotatedRectangleIntersection(rect(a), rect(b), region) == cv::INTERSECT_NONE || region.size() < 3) return 0.0;
  std::vector<cv::Point2f> hull;
  cv::convexHull(region, hull);
  const double inter = cv::contourArea(hull);
  return inter / (area_a + area_b - inter);
}

}  // namespace anchordb::engine::segmentation
