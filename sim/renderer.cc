#include "sim/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "sim/sensor_artefacts.h"

namespace anchordb::sim {
namespace {

constexpr double kEpsilonT = 1e-9;          // hits closer than this along a ray are ignored
constexpr double kShadowToleranceM = 0.01;  // an occluder must be this much before the hit point to shadow it
// Geometry closer than this to the camera plane (optical z) is ignored: neither seen nor casting projector shadows.
constexpr double kNearPlaneM = 1e-3;

// A primitive prepared for one camera pose: everything expressed in its own frame P.
struct Prepared {
  Shape shape = Shape::kBox;
  int object_id = 0;
  Eigen::Matrix3d R_PC = Eigen::Matrix3d::Identity();  // camera directions into the primitive frame
  Eigen::Vector3d p_PC = Eigen::Vector3d::Zero();      // camera origin in P
  Eigen::Vector3d p_PProjector = Eigen::Vector3d::Zero();
  Eigen::Vector3d R_PC_p_CProjector = Eigen::Vector3d::Zero();  // the projector offset as a direction in P
  Eigen::Vector3d half_m = Eigen::Vector3d::Zero();             // box: half extents; cylinder: (r, r, h / 2)
  double radius_m = 0.0;
  double z_min_m = 0.0;  // smallest optical z of the bounding box corners
  // Pixel bounding rectangle of the projection (inclusive, possibly outside the image), and the columns in the
  // image of the projector (a camera with the same intrinsics and orientation at the projector; same rows).
  int u_min = 0, u_max = 0, v_min = 0, v_max = 0;
  int projector_u_min = 0, projector_u_max = 0;
};

struct Interval {
  bool hit = false;
  double t0 = 0.0;
  double t1 = 0.0;
};

// The parameter interval [t0, t1] in which the line o + t d lies inside the solid (in the primitive frame).
// Box: the slab test on all three axes. Cylinder: the slab test on z and the quadratic of the mantle.
inline Interval SlabInterval(double o, double d, double h, Interval in) {
  if (std::abs(d) < 1e-15) {
    if (std::abs(o) > h) in.hit = false;
    return in;
  }
  const double inv = 1.0 / d;
  const double a = (-h - o) * inv;
  const double b = (h - o) * inv;
  in.t0 = std::max(in.t0, std::min(a, b));
  in.t1 = std::min(in.t1, std::max(a, b));
  if (in.t0 > in.t1) in.hit = false;
  return in;
}

inline Interval SolidInterval(const Prepared& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Interval in{true, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  in = SlabInterval(o.z(), d.z(), p.half_m.z(), in);
  if (!in.hit) return in;
  if (p.shape == Shape::kBox) {
    in = SlabInterval(o.x(), d.x(), p.half_m.x(), in);
    if (!in.hit) return in;
    return SlabInterval(o.y(), d.y(), p.half_m.y(), in);
  }
  const double qa = d.x() * d.x() + d.y() * d.y();
  const double qb = o.x() * d.x() + o.y() * d.y();
  const double qc = o.x() * o.x() + o.y() * o.y() - p.radius_m * p.radius_m;
  if (qa < 1e-24) {
    if (qc > 0.0) in.hit = false;
    return in;
  }
  const double disc = qb * qb - qa * qc;
  if (disc < 0.0) return {};
  const double sq = std::sqrt(disc);
  in.t0 = std::max(in.t0, (-qb - sq) / qa);
  in.t1 = std::min(in.t1, (-qb + sq) / qa);
  if (in.t0 > in.t1) in.hit = false;
  return in;
}

// Outward normal (primitive frame) of the face through which the ray o + t d enters the solid, or leaves it if
// the ray starts inside. Decided by the slab or mantle that bounds the interval, not by the hit point, so that
// pixels on an edge get the normal of a face they really see.
Eigen::Vector3d HitNormal(const Prepared& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, bool entering) {
  double best = entering ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  const auto consider = [&](double t, const Eigen::Vector3d& n) {
    if (entering ? t > best : t < best) {
      best = t;
      normal = n;
    }
  };
  const int slab_axes = p.shape == Shape::kBox ? 3 : 1;
  for (int k = 0; k < slab_axes; ++k) {
    const int axis = p.shape == Shape::kBox ? k : 2;
    if (std::abs(d[axis]) < 1e-15) continue;
    // Entering through the face the ray points against, leaving through the other.
    const double sign = (d[axis] > 0.0) == entering ? -1.0 : 1.0;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[axis] = sign;
    consider((sign * p.half_m[axis] - o[axis]) / d[axis], n);
  }
  if (p.shape == Shape::kCylinder) {
    const double qa = d.x() * d.x() + d.y() * d.y();
    if (qa >= 1e-24) {
      const double qb = o.x() * d.x() + o.y() * d.y();
      const double qc = o.x() * o.x() + o.y() * o.y() - p.radius_m * p.radius_m;
      const double sq = std::sqrt(std::max(qb * qb - qa * qc, 0.0));
      const double t = entering ? (-qb - sq) / qa : (-qb + sq) / qa;
      const Eigen::Vector3d x = o + t * d;
      const double radial = std::hypot(x.x(), x.y());
      if (radial > 0.0) consider(t, Eigen::Vector3d(x.x() / radial, x.y() / radial, 0.0));
    }
  }
  return normal;
}

int ClampToInt(double x) { return static_cast<int>(std::clamp(x, -1e8, 1e8)); }

// Prepares a primitive for the camera; returns false if it lies entirely behind the near plane (then it can
// neither be seen nor shadow anything: every primary and projector ray has z >= 0).
bool Prepare(const Primitive& prim, const Eigen::Isometry3d& X_CameraWorld, const PinholeIntrinsics& K,
             double baseline_m, Prepared& out) {
  const Eigen::Isometry3d X_CP = X_CameraWorld * prim.X_WorldPrim;
  out.shape = prim.shape;
  out.object_id = prim.object_id;
  out.R_PC = X_CP.linear().transpose();
  out.p_PC = -(out.R_PC * X_CP.translation());
  out.p_PProjector = out.R_PC * (Eigen::Vector3d(baseline_m, 0.0, 0.0) - X_CP.translation());
  out.R_PC_p_CProjector = out.R_PC * Eigen::Vector3d(baseline_m, 0.0, 0.0);
  if (prim.shape == Shape::kBox) {
    out.half_m = 0.5 * prim.size_m;
  } else {
    out.radius_m = prim.size_m.x();
    out.half_m = Eigen::Vector3d(prim.size_m.x(), prim.size_m.x(), 0.5 * prim.size_m.z());
  }
  // The pixel rectangle of the part of the (bounding) box in front of the plane z = kNearPlaneM: project its corners
  // there and the points where its edges cross that plane.
  std::array<Eigen::Vector3d, 8> corners_C;
  double z_min = std::numeric_limits<double>::infinity();
  double z_max = -std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c_P((corner & 1 ? 1.0 : -1.0) * out.half_m.x(), (corner & 2 ? 1.0 : -1.0) * out.half_m.y(),
                              (corner & 4 ? 1.0 : -1.0) * out.half_m.z());
    corners_C[static_cast<std::size_t>(corner)] = X_CP * c_P;
    z_min = std::min(z_min, corners_C[static_cast<std::size_t>(corner)].z());
    z_max = std::max(z_max, corners_C[static_cast<std::size_t>(corner)].z());
  }
  if (z_max <= kNearPlaneM) return false;
  out.z_min_m = z_min;
  // Columns and rows of the projection of the part in front of the near plane for a camera shifted by
  // `shift_x_m` along the optical x axis.
  const auto project = [&](double shift_x_m, int& u_min, int& u_max, int& v_min, int& v_max) {
    double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
    const auto add = [&](const Eigen::Vector3d& c) {
      const double u = K.fx * (c.x() - shift_x_m) / c.z() + K.cx;
      const double v = K.fy * c.y() / c.z() + K.cy;
      u_lo = std::min(u_lo, u);
      u_hi = std::max(u_hi, u);
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    };
    for (int a = 0; a < 8; ++a) {
      const Eigen::Vector3d& ca = corners_C[static_cast<std::size_t>(a)];
      if (ca.z() >= kNearPlaneM) add(ca);
      for (const int bit : {1, 2, 4}) {
        if (a & bit) continue;  // each edge once, from the corner with the bit clear
        const Eigen::Vector3d& cb = corners_C[static_cast<std::size_t>(a | bit)];
        if ((ca.z() < kNearPlaneM) != (cb.z() < kNearPlaneM)) {
          const double s = (kNearPlaneM - ca.z()) / (cb.z() - ca.z());
          Eigen::Vector3d crossing = ca + s * (cb - ca);
          crossing.z() = kNearPlaneM;
          add(crossing);
        }
      }
    }
    u_min = ClampToInt(std::floor(u_lo)) - 1;
    u_max = ClampToInt(std::ceil(u_hi)) + 1;
    v_min = ClampToInt(std::floor(v_lo)) - 1;
    v_max = ClampToInt(std::ceil(v_hi)) + 1;
  };
  project(0.0, out.u_min, out.u_max, out.v_min, out.v_max);
  int unused_v_min = 0, unused_v_max = 0;  // the projector's rows are the camera's
  project(baseline_m, out.projector_u_min, out.projector_u_max, unused_v_min, unused_v_max);
  return true;
}

// A uniform double in (0, 1] from 53 random bits (portable, unlike std::uniform_real_distribution).
double UniformOpenClosed(std::mt19937_64& rng) {
  return (static_cast<double>(rng() >> 11) + 1.0) * (1.0 / 9007199254740992.0);
}

void CheckInputs(const Scene& scene, const PinholeIntrinsics& K, const SensorModel& sensor) {
  if (K.width <= 0 || K.height <= 0) throw std::invalid_argument("Render: image width and height must be positive");
  if (!(K.fx > 0.0) || !(K.fy > 0.0) || !std::isfinite(K.cx) || !std::isfinite(K.cy)) {
    throw std::invalid_argument("Render: fx and fy must be positive, cx and cy finite");
  }
  if (!(sensor.min_range_m >= 0.0) || !(sensor.max_range_m >= sensor.min_range_m)) {
    throw std::invalid_argument("Render: need 0 <= min_range_m <= max_range_m");
  }
  if (!std::isfinite(sensor.projector_baseline_m) || !std::isfinite(sensor.max_incidence_rad)) {
    throw std::invalid_argument("Render: projector_baseline_m and max_incidence_rad must be finite");
  }
  detail::CheckSensorModel(sensor);
  for (std::size_t i = 0; i < scene.primitives.size(); ++i) {
    const Primitive& p = scene.primitives[i];
    if (p.object_id < 1) {
      throw std::invalid_argument("Render: primitive " + std::to_string(i) + " has object_id < 1");
    }
    const bool box = p.shape == Shape::kBox;
    const bool ok =
        box ? (p.size_m.array() > 0.0).all() && p.size_m.allFinite()
            : p.size_m.x() > 0.0 && p.size_m.z() > 0.0 && std::isfinite(p.size_m.x()) && std::isfinite(p.size_m.z());
    if (!ok) throw std::invalid_argument("Render: primitive " + std::to_string(i) + " has a non-positive size");
  }
}

}  // namespace

Frame Render(const Scene& scene, const PinholeIntrinsics& K, const Eigen::Isometry3d& X_WorldCamera,
             const SensorModel& sensor, std::uint64_t seed) {
  CheckInputs(scene, K, sensor);
  const int width = K.width;
  const int height = K.height;
  const std::size_t pixel_count = static_cast<std::size_t>(width) * height;
  Frame frame;
  frame.width = width;
  frame.height = height;
  frame.depth_mm.assign(pixel_count, 0);
  frame.object_id.assign(pixel_count, 0);
  frame.true_depth_m.assign(pixel_count, 0.0f);

  const Eigen::Isometry3d X_CameraWorld = X_WorldCamera.inverse();
  // A measured pixel (u, v) at depth z >= min range lies in the projector's image at column u - fx * baseline / z.
  const double projector_shift_px = K.fx * sensor.projector_baseline_m / std::max(sensor.min_range_m, kNearPlaneM);
  const double lowest_projector_u = std::min(0.0, -projector_shift_px) - 1.0;
  const double highest_projector_u = width + std::max(0.0, -projector_shift_px) + 1.0;
  std::vector<Prepared> prepared;
  prepared.reserve(scene.primitives.size());
  for (const Primitive& prim : scene.primitives) {
    Prepared p;
    if (!Prepare(prim, X_CameraWorld, K, sensor.projector_baseline_m, p)) continue;
    const bool seen = p.u_max >= 0 && p.u_min < width;
    const bool lit = p.projector_u_max >= lowest_projector_u && p.projector_u_min <= highest_projector_u;
    if (p.v_max < 0 || p.v_min >= height || !(seen || (lit && sensor.shadow))) continue;
    prepared.push_back(p);
  }
  // Nearest first, so that the primary ray loop can stop early.
  std::stable_sort(prepared.begin(), prepared.end(),
                   [](const Prepared& a, const Prepared& b) { return a.z_min_m < b.z_min_m; });
  // Candidates per image row. Primary rays need u in [u_min, u_max]. The projector has the camera's orientation
  // and sits on its x axis, so a point of row v lies in row v of the projector's image too; the projector ray
  // towards pixel (u, v) at depth z can only meet primitives with projector column u - fx * baseline / z in
  // [projector_u_min, projector_u_max].
  std::vector<std::vector<int>> row_candidates(static_cast<std::size_t>(height));
  for (int i = 0; i < static_cast<int>(prepared.size()); ++i) {
    const int v0 = std::max(prepared[i].v_min, 0);
    const int v1 = std::min(prepared[i].v_max, height - 1);
    for (int v = v0; v <= v1; ++v) row_candidates[static_cast<std::size_t>(v)].push_back(i);
  }

  const double cos_max_incidence = std::cos(sensor.max_incidence_rad);
  const Eigen::Vector3d p_CProjector(sensor.projector_baseline_m, 0.0, 0.0);
  // One standard normal per pixel in raster order, drawn whatever the scene, so the white noise depends on the
  // seed and the pixel only (the same sequence as the earlier sensor drew).
  thread_local std::vector<double> white_normal;  // scratch reused by the thread's frames
  if (sensor.noise) {
    white_normal.resize(pixel_count);
    std::mt19937_64 rng(seed);
    for (std::size_t k = 0; k < pixel_count; k += 2) {
      // Marsaglia's polar method: two standard normals per accepted point of the unit disc.
      double a = 0.0, b = 0.0, r2 = 0.0;
      do {
        a = 2.0 * UniformOpenClosed(rng) - 1.0;
        b = 2.0 * UniformOpenClosed(rng) - 1.0;
        r2 = a * a + b * b;
      } while (r2 >= 1.0 || r2 == 0.0);
      const double scale = std::sqrt(-2.0 * std::log(r2) / r2);
      white_normal[k] = a * scale;
      if (k + 1 < pixel_count) white_normal[k + 1] = b * scale;
    }
  }
  // The noiseless depth wherever the sensor can measure (range, incidence, shadow); the measurement stage
  // (sensor_artefacts.h) turns it into the reported depth.
  thread_local std::vector<double> ideal_m;
  ideal_m.assign(pixel_count, 0.0);

  std::vector<Eigen::Vector3d> row_base;  // per candidate of the row: R_PC * (0, y, 1)
  for (int v = 0; v < height; ++v) {
    const std::vector<int>& candidates = row_candidates[static_cast<std::size_t>(v)];
    const double y = (v - K.cy) / K.fy;
    row_base.resize(candidates.size());
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const Prepared& p = prepared[static_cast<std::size_t>(candidates[k])];
      row_base[k] = y * p.R_PC.col(1) + p.R_PC.col(2);
    }
    for (int u = 0; u < width; ++u) {
      const std::size_t index = static_cast<std::size_t>(v) * width + u;

      const double x = (u - K.cx) / K.fx;
      double best_t = std::numeric_limits<double>::infinity();
      int best = -1;
      bool best_entering = true;
      for (std::size_t k = 0; k < candidates.size(); ++k) {
        const Prepared& p = prepared[static_cast<std::size_t>(candidates[k])];
        if (p.z_min_m > best_t) break;
        if (u < p.u_min || u > p.u_max) continue;
        const Interval in = SolidInterval(p, p.p_PC, row_base[k] + x * p.R_PC.col(0));
        if (!in.hit || in.t1 <= kEpsilonT) continue;
        const double t = in.t0 > kEpsilonT ? in.t0 : in.t1;
        if (t < best_t) {
          best_t = t;
          best = candidates[k];
          best_entering = in.t0 > kEpsilonT;
        }
      }
      if (best < 0) continue;
      const Prepared& hit = prepared[static_cast<std::size_t>(best)];
      // The ray direction has z = 1, so the ray parameter is the optical z of the hit.
      const double z_m = best_t;
      frame.object_id[index] = hit.object_id;
      frame.true_depth_m[index] = static_cast<float>(z_m);

      if (z_m < sensor.min_range_m || z_m > sensor.max_range_m) continue;
      const Eigen::Vector3d d_C(x, y, 1.0);
      const Eigen::Vector3d d_P = hit.R_PC * d_C;
      const Eigen::Vector3d n_P = HitNormal(hit, hit.p_PC, d_P, best_entering);
      if (std::abs(n_P.dot(d_P)) < cos_max_incidence * d_P.norm()) continue;  // grazing
      if (sensor.shadow) {
        // The projector ray p_Projector + s (p_Hit - p_Projector), s in (0, 1), in each primitive's frame.
        const double t_limit = 1.0 - kShadowToleranceM / (z_m * d_C - p_CProjector).norm();
        const double projector_u = u - K.fx * sensor.projector_baseline_m / z_m;
        bool shadowed = false;
        for (std::size_t k = 0; k < candidates.size(); ++k) {
          const Prepared& p = prepared[static_cast<std::size_t>(candidates[k])];
          if (p.z_min_m >= z_m) break;  // the projector ray has z in [0, z_m): nothing farther can block it
          if (projector_u < p.projector_u_min || projector_u > p.projector_u_max) continue;
          const Eigen::Vector3d segment_P = z_m * (row_base[k] + x * p.R_PC.col(0)) - p.R_PC_p_CProjector;
          const Interval in = SolidInterval(p, p.p_PProjector, segment_P);
          if (in.hit && in.t0 < t_limit && in.t1 > kEpsilonT) {
            shadowed = true;
            break;
          }
        }
        if (shadowed) continue;
      }
      ideal_m[index] = z_m;
    }
  }
  detail::MeasureDepth(sensor, width, height, seed, ideal_m, white_normal, frame.depth_mm);
  return frame;
}

SensorModel KindSensor() {
  SensorModel sensor;
  sensor.correlated_noise_fraction = 0.0;
  sensor.quantise_disparity = false;
  sensor.lateral_jitter = false;
  sensor.flying_pixels = false;
  sensor.speckle_dropouts = false;
  return sensor;
}

Eigen::Isometry3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = target - eye;
  if (!(forward.norm() > 1e-12)) throw std::invalid_argument("LookAt: eye and target coincide");
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) {
    // Looking straight up or down: let image y (down) point along world +x.
    x = Eigen::Vector3d::UnitX().cross(z);
  }
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d X_WorldCamera = Eigen::Isometry3d::Identity();
  X_WorldCamera.linear().col(0) = x;
  X_WorldCamera.linear().col(1) = y;
  X_WorldCamera.linear().col(2) = z;
  X_WorldCamera.translation() = eye;
  return X_WorldCamera;
}

}  // namespace anchordb::sim
