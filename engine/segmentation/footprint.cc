#include "engine/segmentation/footprint.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace anchordb::engine::segmentation {

namespace {

// The range of `values` between the `trim` and 1 - `trim` quantiles (sorts a copy).
std::pair<double, double> TrimmedRange(std::vector<double>& values, double trim) {
  const std::size_t n = values.size();
  const std::size_t lo = static_cast<std::size_t>(trim * static_cast<double>(n - 1));
  const std::size_t hi = n - 1 - lo;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(lo), values.end());
  const double vlo = values[lo];
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(hi), values.end());
  return {vlo, values[hi]};
}

}  // namespace

Footprint FootprintOf(const std::vector<Eigen::Vector3f>& points_m, double trim) {
  Footprint f;
  if (points_m.empty()) return f;
  f.min_z_m = std::numeric_limits<double>::infinity();
  f.max_z_m = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3f& p : points_m) {
    f.min_z_m = std::min(f.min_z_m, static_cast<double>(p.z()));
    f.max_z_m = std::max(f.max_z_m, static_cast<double>(p.z()));
  }
  // At most 4000 points decide the heading (an even subsample); all of them its extents.
  const std::size_t stride = std::max<std::size_t>(1, points_m.size() / 4000);
  std::vector<double> u, v;
  const auto ranges = [&](double yaw, std::size_t step) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    u.clear();
    v.clear();
    for (std::size_t i = 0; i < points_m.size(); i += step) {
      const double x = points_m[i].x(), y = points_m[i].y();
      u.push_back(c * x + s * y);
      v.push_back(-s * x + c * y);
    }
    return std::make_pair(TrimmedRange(u, trim), TrimmedRange(v, trim));
  };
  // The heading that collapses the faces most: the sum of squared counts of the points' coordinates along both axes
  // in 2 cm bins is largest when the vertical faces of a box lie along the axes (a projection profile). Unlike the
  // least-area rectangle it does not tie between the axes of an L of two faces and the L's diagonal.
  double best_yaw = 0.0, best_score = -1.0;
  std::map<long, double> bins;
  for (int k = 0; k < 90; ++k) {  // headings in 1 deg steps over a quarter turn (a rectangle repeats after that)
    const double yaw = k * std::numbers::pi / 180.0;
    const double c = std::cos(yaw), s = std::sin(yaw);
    double score = 0.0;
    for (int axis = 0; axis < 2; ++axis) {
      bins.clear();
      for (std::size_t i = 0; i < points_m.size(); i += stride) {
        const double x = points_m[i].x(), y = points_m[i].y();
        const double t = axis == 0 ? c * x + s * y : -s * x + c * y;
        bins[static_cast<long>(std::floor(t / 0.02))] += 1.0;
      }
      for (const auto& [bin, count] : bins) score += count * count;
    }
    if (score > best_score) best_score = score, best_yaw = yaw;
  }
  const auto [ru, rv] = ranges(best_yaw, 1);
  double yaw = best_yaw;
  Eigen::Vector2d extent(ru.second - ru.first, rv.second - rv.first);
  const double cu = 0.5 * (ru.first + ru.second), cv = 0.5 * (rv.first + rv.second);
  f.centre_m = Eigen::Vector2d(std::cos(yaw) * cu - std::sin(yaw) * cv, std::sin(yaw) * cu + std::cos(yaw) * cv);
  if (extent.y() > extent.x()) {  // the longer side is the footprint's own x
    std::swap(extent.x(), extent.y());
    yaw += std::numbers::pi / 2;
  }
  while (yaw >= std::numbers::pi / 2) yaw -= std::numbers::pi;
  while (yaw < -std::numbers::pi / 2) yaw += std::numbers::pi;
  f.extent_m = extent;
  f.yaw_rad = yaw;
  return f;
}

Footprint ExtendToWall(const Footprint& f, const Eigen::Vector2d& normal, double offset, double reach_m, double max_angle_rad) {
  const Eigen::Vector2d n = normal.normalized();
  Footprint out = f;
  for (int axis = 0; axis < 2; ++axis) {
    const double yaw = f.yaw_rad + axis * std::numbers::pi / 2;
    const Eigen::Vector2d a(std::cos(yaw), std::sin(yaw));
    const double c = a.dot(n);
    if (std::abs(c) < std::cos(max_angle_rad)) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& corner : FootprintCorners(f)) nearest = std::min(nearest, n.dot(corner) + offset);
    if (!(nearest > 0.0) || nearest > reach_m) return f;
    const double grow = nearest / std::abs(c);
    out.extent_m[axis] += grow;
    out.centre_m -= 0.5 * grow * (c > 0 ? a : Eigen::Vector2d(-a));
    return out;
  }
  return f;
}

std::vector<Eigen::Vector2d> FootprintCorners(const Footprint& f) {
  const Eigen::Vector2d ax(std::cos(f.yaw_rad), std::sin(f.yaw_rad)), ay(-std::sin(f.yaw_rad), std::cos(f.yaw_rad));
  const Eigen::Vector2d hx = 0.5 * f.extent_m.x() * ax, hy = 0.5 * f.extent_m.y() * ay;
  return {f.centre_m - hx - hy, f.centre_m + hx - hy, f.centre_m + hx + hy, f.centre_m - hx + hy};
}

namespace {

double IntersectionArea(const Footprint& a, const Footprint& b) {
  if (!(a.extent_m.prod() > 0.0) || !(b.extent_m.prod() > 0.0)) return 0.0;
  const auto rect = [](const Footprint& f) {
    return cv::RotatedRect(cv::Point2f(static_cast<float>(f.centre_m.x()), static_cast<float>(f.centre_m.y())),
                           cv::Size2f(static_cast<float>(f.extent_m.x()), static_cast<float>(f.extent_m.y())),
                           static_cast<float>(f.yaw_rad * 180.0 / std::numbers::pi));
  };
  std::vector<cv::Point2f> region;
  if (cv::rotatedRectangleIntersection(rect(a), rect(b), region) == cv::INTERSECT_NONE || region.size() < 3) return 0.0;
  std::vector<cv::Point2f> hull;
  cv::convexHull(region, hull);
  return cv::contourArea(hull);
}

}  // namespace

double FootprintIoU(const Footprint& a, const Footprint& b) {
  const double inter = IntersectionArea(a, b);
  if (!(inter > 0.0)) return 0.0;
  return inter / (a.extent_m.prod() + b.extent_m.prod() - inter);
}

double FootprintOverlap(const Footprint& a, const Footprint& b) {
  const double inter = IntersectionArea(a, b);
  return inter > 0.0 ? inter / a.extent_m.prod() : 0.0;
}

}  // namespace anchordb::engine::segmentation
