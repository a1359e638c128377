#pragma once
// Scenes for the registration tests and the registration sweep (bench/registration_sweep.cc): the sparse room of
// issue 13 (a table and one box in an otherwise empty room, rendered by sim/), two viewpoints 0.5 m apart with the
// heading turned by 35 deg, and the localisation error of a stored camera pose. Header-only (the engine tests and
// the bench share it).
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "engine/scene/registration.h"
#include "sim/renderer.h"

namespace anchordb::registration_scenes {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// A room of 10 x 8 m (its walls lie beyond the registration's 4 m range from these viewpoints, so the views hold
// floor, table and box only: the plane-dominated case), a table (1.2 x 0.8 m top at 0.75 m, four legs) and a box
// (0.3 x 0.2 x 0.25 m) on the floor beside it; world frame REP-103, floor top at z = 0.
inline sim::Scene SparseRoom() {
  sim::Scene s;
  const auto box = [&](int id, Vector3d centre, Vector3d size) {
    sim::Primitive p;
    p.object_id = id;
    p.X_WorldPrim = Eigen::Translation3d(centre) * Isometry3d::Identity();
    p.size_m = size;
    s.primitives.push_back(p);
  };
  box(1, {0, 0, -0.05}, {10, 8, 0.1});
  s.objects.push_back({1, "floor", "static"});
  box(2, {1.6, 0, 0.73}, {1.2, 0.8, 0.04});
  for (const double x : {1.05, 2.15}) {
    for (const double y : {-0.35, 0.35}) box(2, {x, y, 0.355}, {0.05, 0.05, 0.71});
  }
  s.objects.push_back({2, "table", "static"});
  box(3, {1.5, 0.75, 0.125}, {0.3, 0.2, 0.25});
  s.objects.push_back({3, "box", "static"});
  return s;
}

// Viewpoint A looks at the table from 1.6 m (camera 1.3 m above the floor); B's eye is 0.5 m from A's and its
// heading turned by 35 deg, the table then off its image centre but inside.
inline Isometry3d ViewA() { return sim::LookAt({0, 0, 1.3}, {1.6, 0, 0.75}); }
inline Isometry3d ViewB() {
  const Vector3d eye(0.25, -0.433, 1.3);
  const double heading = 35.0 * std::numbers::pi / 180.0;
  const double pitch_drop = 0.55 / 1.6;  // the same downward slope as A's
  return sim::LookAt(eye, eye + Vector3d(std::cos(heading), std::sin(heading), -pitch_drop));
}

inline PinholeIntrinsics Kinect(int width = 640, int height = 480) {
  const double f = 525.0 * width / 640.0;
  return {width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0};
}

// The points of a depth image in the frame X_FrameCamera maps the camera into.
inline std::vector<Eigen::Vector3f> Cloud(const sim::Frame& frame, const PinholeIntrinsics& K,
                                          const Isometry3d& X_FrameCamera) {
  std::vector<Eigen::Vector3f> out;
  for (int v = 0; v < frame.height; ++v) {
    for (int u = 0; u < frame.width; ++u) {
      const std::uint16_t d = frame.depth_mm[static_cast<std::size_t>(v) * frame.width + u];
      if (d == 0) continue;
      const double z = d / 1000.0;
      out.push_back((X_FrameCamera * Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z)).cast<float>());
    }
  }
  return out;
}

// The same as the merge registers it (engine::RegistrationCloud: without the pixels at depth discontinuities).
inline std::vector<Eigen::Vector3f> RegistrationInput(const sim::Frame& frame, const PinholeIntrinsics& K,
                                                      const Isometry3d& X_FrameCamera) {
  std::vector<float> depth_m(frame.depth_mm.size());
  for (std::size_t i = 0; i < depth_m.size(); ++i) depth_m[i] = frame.depth_mm[i] / 1000.0f;
  return engine::RegistrationCloud(depth_m, K, X_FrameCamera, engine::IcpParams{}.edge_jump_fraction);
}

// Seeded, portable draws (std distributions differ between standard libraries).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : rng_(seed) {}
  double Uniform() { return static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0); }
  double Normal() {  // Box-Muller
    const double u1 = std::max(Uniform(), 1e-300), u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  Vector3d UnitVector() {
    const double z = 2 * Uniform() - 1, phi = 2 * std::numbers::pi * Uniform(), r = std::sqrt(1 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  std::mt19937_64 rng_;
};

// A map pose moved as registration.h's Matrix6d reads a map-frame error: the position by t (map frame), the
// orientation turned by r about map axes through the position.
inline Isometry3d Perturbed(const Isometry3d& X, const Vector3d& t_m, const Vector3d& r_rad) {
  Isometry3d out = X;
  if (r_rad.norm() > 0) out.linear() = Eigen::AngleAxisd(r_rad.norm(), r_rad.normalized()).toRotationMatrix() * X.linear();
  out.translation() += t_m;
  return out;
}

// The error of a registered earlier camera: its corrected pose (correction * X_CurrentEarlier_stored) against the
// true one, as a position difference [m] and a rotation angle [rad].
struct PoseError {
  double translation_m = 0, rotation_rad = 0;
};
inline PoseError ErrorOf(const Isometry3d& X_CE_estimated, const Isometry3d& X_CE_true) {
  return {(X_CE_estimated.translation() - X_CE_true.translation()).norm(),
          Eigen::AngleAxisd(X_CE_estimated.linear().transpose() * X_CE_true.linear()).angle()};
}

}  // namespace anchordb::registration_scenes
