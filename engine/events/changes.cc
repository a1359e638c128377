#include "engine/events/changes.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/scene/scene_model.h"

namespace anchordb::engine {
namespace {

double Theta(double depth_m, const ChangeParams& p) { return std::max(p.min_theta_m, p.beta * depth_m); }

}  // namespace

std::vector<std::uint8_t> InFrontOfBackground(std::span<const std::uint16_t> depth_mm,
                                              std::span<const std::uint16_t> background_mm, const ChangeParams& p) {
  std::vector<std::uint8_t> out(depth_mm.size(), 0);
  for (std::size_t i = 0; i < depth_mm.size(); ++i) {
    if (depth_mm[i] == 0 || background_mm[i] == 0) continue;
    const double d = depth_mm[i] * 1e-3, b = background_mm[i] * 1e-3;
    out[i] = d < b - Theta(b, p);
  }
  return out;
}

ChangeMasks CompareKeyframes(std::span<const std::uint16_t> before_mm, std::span<const std::uint16_t> after_mm,
                             std::span<const std::uint16_t> background_mm, int width, int height, const ChangeParams& p) {
  const std::vector<std::uint8_t> front_before = InFrontOfBackground(before_mm, background_mm, p);
  const std::vector<std::uint8_t> front_after = InFrontOfBackground(after_mm, background_mm, p);
  ChangeMasks m;
  m.added.assign(after_mm.size(), 0);
  m.removed.assign(after_mm.size(), 0);
  for (std::size_t i = 0; i < after_mm.size(); ++i) {
    const double before = before_mm[i] * 1e-3, after = after_mm[i] * 1e-3;
    // Something new in front of the background: at the start this pixel saw something else (or nothing).
    if (front_after[i]) m.added[i] = before_mm[i] == 0 || std::abs(before - after) > Theta(after, p);
    // In front of the background at the start, and at the end the sensor sees through to (at least) where the
    // object stood. A pixel that is hidden at the end (something nearer) or unmeasured proves nothing.
    if (front_before[i]) m.removed[i] = after_mm[i] != 0 && after > before + Theta(before, p);
  }
  if (p.clean) {
    m.added = CleanMovable(m.added, width, height);
    m.removed = CleanMovable(m.removed, width, height);
  }
  return m;
}

std::vector<Eigen::Vector3f> MaskPoints(std::span<const std::uint8_t> mask, std::span<const std::uint16_t> depth_mm,
                                        const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera) {
  std::vector<Eigen::Vector3f> out;
  const Eigen::Isometry3f X = X_MapCamera.cast<float>();
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * K.width + u;
      if (!mask[i] || depth_mm[i] == 0) continue;
      const float z = depth_mm[i] * 1e-3f;
      out.push_back(X * Eigen::Vector3f(static_cast<float>((u - K.cx) / K.fx) * z, static_cast<float>((v - K.cy) / K.fy) * z, z));
    }
  }
  return out;
}

std::vector<Segment> SegmentMask(std::vector<std::uint8_t> mask, std::span<const std::uint16_t> depth_mm,
                                 const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera, const ChangeParams& p) {
  if (p.clean) mask = CleanMovable(mask, K.width, K.height);
  return ClusterSegments(MaskPoints(mask, depth_mm, K, X_MapCamera), p.segments);
}

Visibility CheckVisibility(const std::vector<Eigen::Vector3f>& points_map, std::span<const std::uint16_t> depth_mm,
                           const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera, const ChangeParams& p,
                           double max_range_m) {
  Visibility v;
  const Eigen::Isometry3d X_CM = X_MapCamera.inverse();
  for (const auto& q : points_map) {
    const Eigen::Vector3d c = X_CM * q.cast<double>();
    if (c.z() <= 0.1 || c.z() > max_range_m) {
      ++v.outside;
      continue;
    }
    const long u = std::lround(K.fx * c.x() / c.z() + K.cx), row = std::lround(K.fy * c.y() / c.z() + K.cy);
    if (u < 0 || row < 0 || u >= K.width || row >= K.height) {
      ++v.outside;
      continue;
    }
    const std::uint16_t d_mm = depth_mm[static_cast<std::size_t>(row) * K.width + static_cast<std::size_t>(u)];
    if (d_mm == 0) {
      ++v.unmeasured;
      continue;
    }
    const double d = d_mm * 1e-3, theta = Theta(c.z(), p);
    if (d > c.z() + theta) ++v.seen_through;
    else if (d < c.z() - theta) ++v.hidden;
    else ++v.confirmed;
  }
  return v;
}

std::vector<std::uint16_t> RenderDepthMm(const std::vector<Eigen::Vector3f>& points_map, const PinholeIntrinsics& K,
                                         const Eigen::Isometry3d& X_MapCamera) {
  std::vector<std::uint16_t> out(static_cast<std::size_t>(K.width) * K.height, 0);
  const Eigen::Isometry3f X_CM = X_MapCamera.inverse().cast<float>();
  for (const auto& q : points_map) {
    const Eigen::Vector3f c = X_CM * q;
    if (c.z() <= 0.05f || c.z() > 65.0f) continue;
    const double u = K.fx * c.x() / c.z() + K.cx, v = K.fy * c.y() / c.z() + K.cy;
    const auto mm = static_cast<std::uint16_t>(std::lround(c.z() * 1000.0f));
    for (int dv = 0; dv < 2; ++dv) {
      for (int du = 0; du < 2; ++du) {
        const long x = static_cast<long>(std::floor(u)) + du, y = static_cast<long>(std::floor(v)) + dv;
        if (x < 0 || y < 0 || x >= K.width || y >= K.height) continue;
        std::uint16_t& d = out[static_cast<std::size_t>(y) * K.width + static_cast<std::size_t>(x)];
        if (d == 0 || mm < d) d = mm;
      }
    }
  }
  return out;
}

double MatchDistance(const Segment& s, const Eigen::Vector3d& centroid_m, const Eigen::Vector3d&) {
  return (s.centroid_m - centroid_m).norm();
}

namespace {
double Volume(const Eigen::Vector3d& e) {
  return std::max(e.x(), 0.02) * std::max(e.y(), 0.02) * std::max(e.z(), 0.02);
}
}  // namespace

bool Matches(const Segment& s, const Eigen::Vector3d& centroid_m, const Eigen::Vector3d& extent_m, const MatchParams& p) {
  const Eigen::Vector3d e = s.Extent();
  const double reach = std::max({p.centroid_tolerance_m, 0.5 * e.head<2>().maxCoeff(), 0.5 * extent_m.head<2>().maxCoeff()});
  if (MatchDistance(s, centroid_m, extent_m) > reach) return false;
  const double a = Volume(e), b = Volume(extent_m);
  return std::min(a, b) / std::max(a, b) >= p.min_size_ratio;
}

double SizeSimilarity(const Eigen::Vector3d& extent_a_m, const Eigen::Vector3d& extent_b_m) {
  std::array<double, 3> a = {std::max(extent_a_m.x(), 0.01), std::max(extent_a_m.y(), 0.01), std::max(extent_a_m.z(), 0.01)};
  std::array<double, 3> b = {std::max(extent_b_m.x(), 0.01), std::max(extent_b_m.y(), 0.01), std::max(extent_b_m.z(), 0.01)};
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double product = 1.0;
  for (int k = 0; k < 3; ++k) product *= std::min(a[k], b[k]) / std::max(a[k], b[k]);
  return std::cbrt(product);
}

}  // namespace anchordb::engine
