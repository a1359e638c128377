#include "engine/scene/merge.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "engine/scene/merge_tolerance.h"
#include "engine/scene/projection.h"

namespace anchordb::engine {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Ray of pixel (u, v) in the optical frame, with z = 1 (so a depth is its parameter).
Eigen::Vector3d PixelRay(const PinholeIntrinsics& K, int u, int v) {
  return {(u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0};
}

// Depth (along the current ray, as the current camera's z) where the ray o + t d, given in the earlier camera's
// frame, leaves that camera's view frustum (side planes and the far plane). +inf if it never leaves.
double FrustumExit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const PinholeIntrinsics& K, double far_m) {
  const double xmin = (0.0 - K.cx) / K.fx, xmax = (K.width - K.cx) / K.fx;
  const double ymin = (0.0 - K.cy) / K.fy, ymax = (K.height - K.cy) / K.fy;
  const Eigen::Vector3d normals[4] = {{1, 0, -xmin}, {-1, 0, xmax}, {0, 1, -ymin}, {0, -1, ymax}};
  double t_exit = std::numeric_limits<double>::infinity();
  for (const auto& n : normals) {
    const double nd = n.dot(d);
    if (nd < 0) t_exit = std::min(t_exit, -n.dot(o) / nd);
  }
  if (d.z() > 0) t_exit = std::min(t_exit, (far_m - o.z()) / d.z());
  return t_exit;
}

struct Projection {
  bool inside = false;
  int u = 0, v = 0;
  double z = 0.0;
};

Projection Project(const Eigen::Vector3d& p, const PinholeIntrinsics& K, double far_m) {
  Projection out;
  if (p.z() <= 0.05 || p.z() > far_m) return out;
  const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
  if (u < 0 || v < 0 || u >= K.width || v >= K.height) return out;
  out.inside = true;
  out.u = static_cast<int>(u);
  out.v = static_cast<int>(v);
  out.z = p.z();
  return out;
}

// The earlier sensor's effective field of view in its image: the bounding box of its measured pixels. Real depth
// cameras leave bands at the image border without depth (e.g. a Kinect's registration border); there the earlier
// camera saw nothing, which premise 1 must not take for "seen and empty".
struct PixelBox {
  int u_min, u_max, v_min, v_max;
  bool Contains(int u, int v) const { return u >= u_min && u <= u_max && v >= v_min && v <= v_max; }
};

// Rear projection P(s_v, V^j) of lines 9-11: the depth (along the current ray) up to which the earlier camera
// provably saw free space behind the point at `from_depth` -- the farthest place that provably holds no static
// structure. The ray is followed in steps of 0.5 % of the depth while it stays inside the earlier frustum (side
// planes, far plane, effective field of view) and the earlier camera saw through it: it measured something farther
// there (beyond theta), or nothing inside a wide unknown area (beyond its range). Where the earlier camera saw
// nothing at all (beyond its range) this is the frustum's rear boundary, as in the thesis; where it saw through
// the point but the surface behind it from the current view was hidden from it, the ray stops where it enters
// that hidden region.
double FreeSpaceExit(const Eigen::Isometry3d& X_prior_C, const Eigen::Vector3d& ray_C, double from_depth,
                     const PinholeIntrinsics& K_prior, const cv::Mat& nearest_m, const cv::Mat& unknown_distance_px,
                     const PixelBox& seen, double margin_per_m, double min_unknown_px, const MergeParams& params) {
  const double exit = FrustumExit(X_prior_C.translation(), X_prior_C.linear() * ray_C, K_prior, params.frustum_far_m);
  if (!std::isfinite(exit)) return exit;
  double free_to = from_depth;
  for (double t = from_depth * 1.005; t < exit; t *= 1.005) {
    const Eigen::Vector3d p = X_prior_C * (ray_C * t);
    if (p.z() <= 0.05) return free_to;
    const double u = K_prior.fx * p.x() / p.z() + K_prior.cx, v = K_prior.fy * p.y() / p.z() + K_prior.cy;
    if (u < 0 || v < 0 || u >= K_prior.width || v >= K_prior.height) return free_to;
    const int iu = static_cast<int>(u), iv = static_cast<int>(v);
    if (!seen.Contains(iu, iv)) return free_to;
    const float measured = nearest_m.at<float>(iv, iu);  // the nearest within the pose tolerance's window
    if (measured < std::numeric_limits<float>::max()) {
      // at or behind what the earlier camera saw (theta, and the pose uncertainty at this depth)
      if (p.z() >= measured - params.beta * measured - margin_per_m * t) return free_to;
    } else if (unknown_distance_px.at<float>(iv, iu) < min_unknown_px) {
      return free_to;  // a dropout: no evidence either way
    }
    free_to = t;
  }
  return exit;
}

// The image slope [m per px] of a depth image (0 = unknown) at pixel i along one axis (`step` = 1 or the width):
// central differences over +-2 px where the surface is continuous (the neighbour within beta of the pixel's
// depth), one-sided where only one side is, 0 at discontinuities and near the border; clamped to 1.5 % of the depth
// per px (a surface seen at ~80 deg incidence). Evaluated only where a premise needs it.
float SlopeAt(const std::vector<float>& d, std::size_t i, std::ptrdiff_t step, bool inside, float beta) {
  const float c = d[i];
  if (!inside || c <= 0.0f) return 0.0f;
  const float ahead = d[i + 2 * step], behind = d[i - 2 * step];
  const float tol = beta * c, limit = 0.015f * c;
  const bool a = ahead > 0.0f && std::abs(ahead - c) < tol, b = behind > 0.0f && std::abs(behind - c) < tol;
  const float g = a && b ? 0.25f * (ahead - behind) : a ? 0.5f * (ahead - c) : b ? 0.5f * (c - behind) : 0.0f;
  return std::clamp(g, -limit, limit);
}

struct Slope {
  float du = 0.0f, dv = 0.0f;
};
Slope SlopeOf(const std::vector<float>& d, int width, int height, int u, int v, float beta) {
  const std::size_t i = static_cast<std::size_t>(v) * width + u;
  return {SlopeAt(d, i, 1, u >= 2 && u + 2 < width, beta), SlopeAt(d, i, width, v >= 2 && v + 2 < height, beta)};
}

// The k-sigma displacement of the earlier model's points under the pose uncertainty, median over an even subset:
// in the current image [px] (the larger of the two images) and along the current camera's z [m].
void MedianTolerance(const PoseUncertainty& uncertainty, const std::vector<Eigen::Vector3f>& cloud_C,
                     const PinholeIntrinsics& K, double k, MergeModelReport& report) {
  std::vector<double> px, m;
  const std::size_t step = std::max<std::size_t>(1, cloud_C.size() / 256);
  for (std::size_t i = 0; i < cloud_C.size(); i += step) {
    const Eigen::Vector3d p = cloud_C[i].cast<double>();
    if (p.z() <= 0.05) continue;
    const Motion A = PoseUncertainty::InCurrent(p);
    px.push_back(k * uncertainty.Pixels(A, p, K));
    m.push_back(k * uncertainty.Z(A));
  }
  if (px.empty()) return;
  std::nth_element(px.begin(), px.begin() + px.size() / 2, px.end());
  std::nth_element(m.begin(), m.begin() + m.size() / 2, m.end());
  report.tolerance_px = px[px.size() / 2];
  report.tolerance_m = m[m.size() / 2];
}

// What the premises read of one earlier model's background image, built once per model.
constexpr int kBuckets = 9;
constexpr int kRadii[kBuckets] = {2, 3, 4, 6, 8, 12, 16, 24, 32};

int BucketOf(double px) {
  int b = 0;
  while (b + 1 < kBuckets && kRadii[b] < px) ++b;
  return b;
}

struct PriorImages {
  cv::Mat unknown_distance_px;       // distance [px] of every earlier pixel to the nearest measured one (0 where measured)
  PixelBox seen;                     // the earlier sensor's effective field of view
  cv::Mat nearest_within[kBuckets];  // nearest measured depth within square windows of kRadii (unknown = +inf)
};

PriorImages PriorImagesOf(const PriorModel& prior) {
  const PinholeIntrinsics& Kp = prior.K;
  PriorImages out;
  cv::Mat unknown(Kp.height, Kp.width, CV_8U);
  for (std::size_t q = 0; q < prior.background_m.size(); ++q) unknown.data[q] = prior.background_m[q] > 0.0f ? 0 : 255;
  cv::distanceTransform(unknown, out.unknown_distance_px, cv::DIST_L2, cv::DIST_MASK_3);
  out.seen = PixelBox{Kp.width, -1, Kp.height, -1};
  for (int v = 0; v < Kp.height; ++v) {
    for (int u = 0; u < Kp.width; ++u) {
      if (prior.background_m[static_cast<std::size_t>(v) * Kp.width + u] > 0.0f) {
        out.seen.u_min = std::min(out.seen.u_min, u), out.seen.u_max = std::max(out.seen.u_max, u);
        out.seen.v_min = std::min(out.seen.v_min, v), out.seen.v_max = std::max(out.seen.v_max, v);
      }
    }
  }
  // Premise 2's test. The steps are fine enough (1.5x) that rounding a pixel's displacement up to the next one costs
  // little.
  cv::Mat earlier(Kp.height, Kp.width, CV_32F);
  for (std::size_t q = 0; q < prior.background_m.size(); ++q) {
    earlier.ptr<float>()[q] = prior.background_m[q] > 0.0f ? prior.background_m[q] : std::numeric_limits<float>::max();
  }
  for (int b = 0; b < kBuckets; ++b) {
    cv::erode(earlier, out.nearest_within[b], cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kRadii[b] + 1, 2 * kRadii[b] + 1)),
              cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  }
  return out;
}

// Everything one pixel's decision reads: the earlier model and its images, the rasterised earlier model s_u, the
// current pose uncertainty and parameters.
struct MergeInputs {
  const PriorModel& prior;
  const PriorImages& images;
  const std::vector<float>& s_u;
  const Eigen::Isometry3d X_prior_C;
  const PoseUncertainty& uncertainty;
  const PinholeIntrinsics& K;
  const MergeParams& params;
  float beta;
  double k;  // pose_sigma_factor
};

// Premise 2 for a point that projects into the earlier image (proj, own = the earlier depth there): nothing stood in
// front of (or at) the point as seen from the earlier camera -- at the point's depth it would have been seen as
// static. The point's own line of sight must show something farther by theta and by what the uncertainty may change
// there (the slope-aware sigma of the earlier image), or nothing; and since the point may lie beside where it
// projects, nothing nearer than the point may have been seen within the window its displacement spans either --
// except the surface under the point continuing (a slanted floor or table top) -- and at least occlusion_px where
// the own pixel has no depth, as a dropped pixel (grazing angle, shadow) is no evidence of free space.
bool Occluded(const MergeInputs& m, const Projection& proj, float own, double px_E, double margin_E, const Slope& g_E) {
  const auto window_clear = [&](double min_px) {
    const int b = BucketOf(std::max(min_px, px_E));
    const float nearest = m.images.nearest_within[b].at<float>(proj.v, proj.u);
    if (nearest >= proj.z + m.beta * proj.z) return true;
    const double continuing = own - std::hypot(g_E.du, g_E.dv) * kRadii[b] * std::sqrt(2.0);
    return own > 0.0f && nearest >= continuing - m.beta * own;
  };
  return own > 0.0f ? own < proj.z + margin_E || !window_clear(1.0) : !window_clear(m.params.occlusion_px);
}

// Premise 3: the transformed model has points at depth sv near pixel (u, v): within neighbourhood_px as in the
// thesis, and within neighbourhood_sigma_factor sigmas of the point's displacement in the current image (sampled
// sparsely) where an earlier surface, continued along its slope, passes the pixel within theta and the point's z
// uncertainty.
bool NeighbourAtDepth(const MergeInputs& m, int u, int v, float su, float sv, double sigma_px_C, const Motion& A_C) {
  const PinholeIntrinsics& K = m.K;
  const float theta = m.beta * sv;
  const int r = m.params.neighbourhood_px;
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= K.width || vv >= K.height) continue;
      const float q = m.s_u[static_cast<std::size_t>(vv) * K.width + uu];
      if (q > 0.0f && std::abs(q - sv) < theta) return true;
    }
  }
  const int reach = static_cast<int>(std::ceil(m.params.neighbourhood_sigma_factor * sigma_px_C));
  if (reach <= r) return false;
  const double tol = std::hypot(static_cast<double>(theta), m.k * m.uncertainty.Z(A_C));
  const int stride = std::max(1, reach / 4);
  for (int dv = -reach; dv <= reach; dv += stride) {
    for (int du = -reach; du <= reach; du += stride) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= K.width || vv >= K.height) continue;
      const std::size_t q = static_cast<std::size_t>(vv) * K.width + uu;
      if (m.s_u[q] <= 0.0f) continue;
      const Slope g = SlopeOf(m.s_u, K.width, K.height, uu, vv, m.beta);
      const double continued = m.s_u[q] - g.du * du - g.dv * dv;
      // Only a surface other than the one the earlier model shows at this pixel (an edge the error may have
      // shifted over it): the surface behind a new object, continued, is no evidence against it.
      if (su > 0.0f && std::abs(continued - su) < m.beta * su) continue;
      if (std::abs(continued - sv) < tol) return true;
    }
  }
  return false;
}

// Lines 2-11 for pixel (u, v) whose current depth sv is measured: the decision, and in `depth` the pixel's new depth
// when the decision replaces it (kReplacedFarther, kRearProjected).
MergeDecision DecideMeasured(const MergeInputs& m, int u, int v, float su, float sv, float& depth) {
  const PinholeIntrinsics& Kp = m.prior.K;
  const float theta = m.beta * sv;
  // Line 3-4 (the pose uncertainty enters below: a surface the error moved farther fails premise 2's margin).
  if (su > 0.0f && std::abs(su - sv) < theta) return MergeDecision::kSupported;
  if (su > 0.0f && su < sv) return MergeDecision::kNearer;  // the static background is known to lie behind
  // Lines 6-11 need the premises for s_v^i, each under the pose uncertainty of the point.
  const Eigen::Vector3d ray = PixelRay(m.K, u, v);
  const Eigen::Vector3d p_C = ray * static_cast<double>(sv);
  const Eigen::Vector3d p_prior = m.X_prior_C * p_C;
  const Projection proj = Project(p_prior, Kp, m.params.frustum_far_m);
  if (!proj.inside) return MergeDecision::kRejectedFov;  // premise 1
  const float own = m.prior.background_m[static_cast<std::size_t>(proj.v) * Kp.width + proj.u];
  if (own > 0.0f && own < proj.z + m.beta * proj.z) return MergeDecision::kRejectedOcclusion;  // whatever the uncertainty
  const Motion A_C = PoseUncertainty::InCurrent(p_C), A_E = m.uncertainty.InEarlier(p_C);
  const double px_E = m.k * m.uncertainty.Pixels(A_E, p_prior, Kp), sigma_px_C = m.uncertainty.Pixels(A_C, p_C, m.K);
  if (std::max(px_E, m.k * sigma_px_C) > m.params.max_pose_tolerance_px) return MergeDecision::kRejectedUncertain;
  const int margin_px = static_cast<int>(std::ceil(px_E));
  if (!m.images.seen.Contains(proj.u - margin_px, proj.v - margin_px) || !m.images.seen.Contains(proj.u + margin_px, proj.v + margin_px)) {
    return MergeDecision::kRejectedFov;  // premise 1 under the uncertainty: well inside the earlier field of view
  }
  const Slope g_E = SlopeOf(m.prior.background_m, Kp.width, Kp.height, proj.u, proj.v, m.beta);
  const double margin_E = std::hypot(static_cast<double>(m.beta) * proj.z, m.k * m.uncertainty.Slanted(A_E, p_prior, Kp, g_E.du, g_E.dv));
  if (Occluded(m, proj, own, px_E, margin_E, g_E)) return MergeDecision::kRejectedOcclusion;
  if (NeighbourAtDepth(m, u, v, su, sv, sigma_px_C, A_C)) return MergeDecision::kRejectedNeighbourhood;
  if (su > sv) {  // lines 6-8: the earlier camera must have seen through the point (measured farther there)
    if (!(own > proj.z + margin_E)) return MergeDecision::kNotSeenThrough;
    depth = su;
    return MergeDecision::kReplacedFarther;
  }
  // su unknown: lines 9-11, rear projection.
  const double min_unknown_px = std::max(m.params.rear_projection_min_unknown_px, px_E);
  if (own == 0.0f && m.images.unknown_distance_px.at<float>(proj.v, proj.u) < min_unknown_px) {
    return MergeDecision::kRejectedDropout;  // a dropout next to measured structure: not seen through
  }
  const double margin_per_m = m.k * m.uncertainty.Z(A_E) / proj.z;
  const double exit = FreeSpaceExit(m.X_prior_C, ray, sv, Kp, m.images.nearest_within[BucketOf(std::max(1.0, px_E))],
                                    m.images.unknown_distance_px, m.images.seen, margin_per_m, min_unknown_px, m.params);
  // Beyond theta of both depths: Algorithm 1 would take a background within theta of its own depth for the surface
  // measured now.
  if (std::isfinite(exit) && exit > sv + theta && exit - sv >= m.params.beta * exit) {
    depth = static_cast<float>(exit);
    return MergeDecision::kRearProjected;
  }
  return MergeDecision::kRearNotBehind;
}

// A decision applied to pixel i of (s_v, w) and counted in the report.
void Apply(MergeDecision d, std::size_t i, float depth, std::vector<float>& s_v, std::vector<float>& w, MergeModelReport& report) {
  switch (d) {
    case MergeDecision::kFilledUnknown: s_v[i] = depth, w[i] = 1.0f, ++report.filled_unknown; break;
    case MergeDecision::kSupported: w[i] += 1.0f, ++report.supported; break;
    case MergeDecision::kRejectedFov: ++report.rejected_fov; break;
    case MergeDecision::kRejectedOcclusion:
    case MergeDecision::kNotSeenThrough:
    case MergeDecision::kRejectedDropout: ++report.rejected_occlusion; break;
    case MergeDecision::kRejectedUncertain: ++report.rejected_uncertain; break;
    case MergeDecision::kRejectedNeighbourhood: ++report.rejected_neighbourhood; break;
    case MergeDecision::kReplacedFarther: s_v[i] = depth, w[i] = 1.0f, ++report.replaced_farther; break;
    case MergeDecision::kRearProjected: s_v[i] = depth, w[i] = 1.0f, ++report.rear_projected; break;
    case MergeDecision::kNothing:
    case MergeDecision::kNearer:
    case MergeDecision::kRearNotBehind:
    case MergeDecision::kCount: break;
  }
}

// Lines 2-11 of Algorithm 2 for one earlier model, rasterised into the current view as s_u, on S_v (s_v, w).
void MergeOne(const PriorModel& prior, const std::vector<float>& s_u, const Eigen::Isometry3d& X_C_prior,
              const PoseUncertainty& uncertainty, const PinholeIntrinsics& K, const MergeParams& params,
              std::vector<float>& s_v, std::vector<float>& w, MergeModelReport& report) {
  const PriorImages images = PriorImagesOf(prior);
  const MergeInputs m{prior, images, s_u, X_C_prior.inverse(), uncertainty, K, params, static_cast<float>(params.beta),
                      params.pose_sigma_factor};
  if (params.record_decisions) report.decisions.assign(s_v.size(), static_cast<std::uint8_t>(MergeDecision::kNothing));
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * K.width + u;
      const float su = s_u[i], sv = s_v[i];
      float depth = su;
      MergeDecision d = MergeDecision::kNothing;
      if (sv != 0.0f) d = DecideMeasured(m, u, v, su, sv, depth);
      else if (su > 0.0f) d = MergeDecision::kFilledUnknown;  // nothing measured here now: the earlier background fills the gap
      Apply(d, i, depth, s_v, w, report);
      if (params.record_decisions) report.decisions[i] = static_cast<std::uint8_t>(d);
    }
  }
}

}  // namespace

std::vector<float> Rasterise(const std::vector<Eigen::Vector3f>& points_C, const PinholeIntrinsics& K, int closing_px) {
  std::vector<float> depth(static_cast<std::size_t>(K.width) * K.height, 0.0f);
  for (const auto& p : points_C) {
    if (p.z() <= 0.05f) continue;
    const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
    if (u < 0 || v < 0 || u >= K.width || v >= K.height) continue;
    float& d = depth[static_cast<std::size_t>(v) * K.width + static_cast<std::size_t>(u)];
    if (d == 0.0f || p.z() < d) d = p.z();
  }
  if (closing_px > 1) {
    cv::Mat m(K.height, K.width, CV_32F, depth.data());
    cv::Mat closed;
    cv::morphologyEx(m, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(closing_px, closing_px)));
    for (std::size_t i = 0; i < depth.size(); ++i) {
      if (depth[i] == 0.0f) depth[i] = closed.ptr<float>()[i];  // only holes are filled; measured pixels stay
    }
  }
  return depth;
}

double FrustumOverlap(const std::vector<Eigen::Vector3f>& probe_map, const PinholeIntrinsics& K,
                      const Eigen::Isometry3d& X_MapCamera, double far_m) {
  if (probe_map.empty()) return 0.0;
  const Eigen::Isometry3d X_CM = X_MapCamera.inverse();
  std::size_t inside = 0;
  for (const auto& p : probe_map) inside += Project(X_CM * p.cast<double>(), K, far_m).inside;
  return static_cast<double>(inside) / probe_map.size();
}

MergeResult MergeAndApplyFirstFrame(SceneModelState& state, std::span<const std::uint16_t> depth, double units_per_m,
                                    std::span<const std::uint8_t> dynamic_mask, const SceneModelParams& scene_params,
                                    const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera,
                                    const std::vector<PriorModel>& priors, const MergeParams& params) {
  MergeResult result;
  const std::size_t n = static_cast<std::size_t>(K.width) * K.height;
  std::vector<float> frame_m(n);
  for (std::size_t i = 0; i < n; ++i) {
    // Dynamic pixels (a tracked person) are no evidence of the static scene.
    const bool dyn = !dynamic_mask.empty() && dynamic_mask[i];
    frame_m[i] = dyn ? 0.0f : static_cast<float>(depth[i] / units_per_m);
  }
  const Eigen::Isometry3d X_CM = X_MapCamera.inverse();
  // The ICP target (the current frame: downsampled, normals, search tree) is prepared once for every earlier model.
  IcpTarget icp_target;
  if (params.strategy != MergeStrategy::kNaiveWithoutIcp && !priors.empty()) {
    const auto start = Clock::now();
    icp_target = PrepareIcpTarget(
        RegistrationCloud(frame_m, K, Eigen::Isometry3d::Identity(), params.icp.edge_jump_fraction), params.icp);
    result.timing.icp_ms += MsSince(start);
  }

  std::vector<float> s_v = frame_m;            // line 1: S_v <- F_t
  std::vector<float> w(n, 1.0f);
  std::vector<float> naive(n, 0.0f);           // z-buffer of all transformed models (naive strategies)

  for (const PriorModel& prior : priors) {
    MergeModelReport report;
    report.id = prior.id;
    auto start = Clock::now();
    std::vector<Eigen::Vector3f> cloud_C = BackProject(prior.background_m, prior.K, X_CM * prior.X_MapCamera);
    Eigen::Isometry3d X_C_prior = X_CM * prior.X_MapCamera;  // pose of the earlier camera in the current one
    // The uncertainty of X_C_prior the premises allow for: the registration's remaining one, else the prior's.
    Matrix6d covariance_C = RelativePoseCovariance(X_MapCamera, params.current_pose_covariance_map,
                                                   prior.X_MapCamera, prior.pose_covariance_map);
    if (params.strategy != MergeStrategy::kNaiveWithoutIcp && !cloud_C.empty() && icp_target.points > 0) {
      report.icp = AlignIcp(RegistrationCloud(prior.background_m, prior.K, X_CM * prior.X_MapCamera,
                                              params.icp.edge_jump_fraction),
                            icp_target, covariance_C);
      covariance_C = report.icp.covariance;
      if (report.icp.accepted) {
        report.icp_applied = true;
        for (auto& p : cloud_C) p = (report.icp.correction.cast<float>() * p);
        X_C_prior = report.icp.correction * X_C_prior;
      }
    }
    result.timing.icp_ms += MsSince(start);
    const PoseUncertainty uncertainty(covariance_C, X_C_prior);
    MedianTolerance(uncertainty, cloud_C, K, params.pose_sigma_factor, report);
    if (params.strategy == MergeStrategy::kAlgorithm2 && report.tolerance_px > params.max_pose_tolerance_px) {
      // Never worse than no merge: the premises cannot decide anything under this uncertainty.
      char why[160];
      std::snprintf(why, sizeof why,
                    "; remaining pose uncertainty %.1f px / %.1f cm (%.1f sigma, median over the model) beyond the "
                    "%.0f px the premises can use: not merged",
                    report.tolerance_px, report.tolerance_m * 100, params.pose_sigma_factor, params.max_pose_tolerance_px);
      report.fallback = std::string("registration ") + (report.icp_applied ? "accepted" : "not accepted") + " (" +
                        (report.icp.verdict.empty() ? "not run" : report.icp.verdict) + ")" + why;
      result.models.push_back(report);
      continue;
    }
    start = Clock::now();
    const std::vector<float> s_u = Rasterise(cloud_C, K, params.closing_px);
    for (float v : s_u) report.rasterised_pixels += v > 0.0f;
    result.timing.rasterise_ms += MsSince(start);
    start = Clock::now();

    if (params.strategy != MergeStrategy::kAlgorithm2) {
      for (std::size_t i = 0; i < n; ++i) {
        if (s_u[i] > 0.0f && (naive[i] == 0.0f || s_u[i] < naive[i])) naive[i] = s_u[i];
      }
    } else {
      MergeOne(prior, s_u, X_C_prior, uncertainty, K, params, s_v, w, report);
    }
    result.timing.merge_ms += MsSince(start);
    result.models.push_back(report);
  }

  if (params.strategy == MergeStrategy::kAlgorithm2) {
    state.background_m = s_v;
    state.weight = w;
  } else {
    state.background_m = naive;  // the transformed earlier background is taken as it is
    state.weight.assign(n, 1.0f);
  }
  ApplyFrame(state, depth, units_per_m, dynamic_mask, scene_params);
  return result;
}

std::optional<CameraCorrection> CorrectedCameraPose(const MergeResult& result, const Eigen::Isometry3d& X_MapCamera) {
  const MergeModelReport* best = nullptr;
  for (const auto& r : result.models) {
    if (r.icp_applied && (!best || r.icp.fitness_m2 < best->icp.fitness_m2)) best = &r;
  }
  if (!best) return std::nullopt;
  return CameraCorrection{best->id, X_MapCamera * best->icp.correction.inverse()};
}

}  // namespace anchordb::engine
