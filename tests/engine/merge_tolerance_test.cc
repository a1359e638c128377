// The pose uncertainty propagated to a point (merge_tolerance.h) against sampling: relative poses drawn from the
// covariance (left perturbation in the current frame), the point moved, projected and measured as the merge does.
#include "engine/scene/merge_tolerance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace anchordb::engine {
namespace merge_tolerance_test {

const PinholeIntrinsics kK{640, 480, 525.0, 525.0, 319.5, 239.5};

Eigen::Isometry3d ExpLeft(const Vector6d& xi) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w = xi.tail<3>();
  if (w.norm() > 0) X.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  X.translation() = xi.head<3>();
  return X;
}

struct Sampled {
  double current_px = 0, current_z = 0, earlier_px = 0, earlier_z = 0, slanted = 0;
};

// Root mean squares over draws xi ~ N(0, diag(sigmas^2)).
Sampled Sample(const Vector6d& sigmas, const Eigen::Isometry3d& X_CE, const Eigen::Vector3d& p_C,
               const Eigen::Vector3d& plane_normal_C) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;  // only the statistics are compared, not exact values
  const auto project = [](const Eigen::Vector3d& p) {
    return Eigen::Vector2d(kK.fx * p.x() / p.z() + kK.cx, kK.fy * p.y() / p.z() + kK.cy);
  };
  const Eigen::Vector3d p_E = X_CE.inverse() * p_C;
  // The depth a fixed pixel (that of p_C) shows of the plane through p_C with this normal, when the plane moves.
  const Eigen::Vector3d ray = p_C / p_C.z();
  Sampled s;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = sigmas[k] * normal(rng);
    const Eigen::Isometry3d E = ExpLeft(xi);
    const Eigen::Vector3d moved_C = E * p_C;  // a point of the earlier model, in the current frame
    s.current_px += (project(moved_C) - project(p_C)).squaredNorm();
    s.current_z += std::pow(moved_C.z() - p_C.z(), 2);
    const Eigen::Vector3d moved_E = (E * X_CE).inverse() * p_C;  // a current point, in the earlier frame
    s.earlier_px += (project(moved_E) - project(p_E)).squaredNorm();
    s.earlier_z += std::pow(moved_E.z() - p_E.z(), 2);
    const Eigen::Vector3d n_moved = E.linear() * plane_normal_C;
    const double t = n_moved.dot(moved_C) / n_moved.dot(ray);
    s.slanted += std::pow(t - p_C.z(), 2);
  }
  s.current_px = std::sqrt(s.current_px / n), s.current_z = std::sqrt(s.current_z / n);
  s.earlier_px = std::sqrt(s.earlier_px / n), s.earlier_z = std::sqrt(s.earlier_z / n);
  s.slanted = std::sqrt(s.slanted / n);
  return s;
}

TEST(MergeToleranceTest, FirstOrderPropagationMatchesSampling) {
  // A table top 1.8 m ahead, seen 25 deg from above; the earlier camera 0.45 m to the side, turned by 35 deg.
  const double tilt = 25.0 * M_PI / 180.0;
  const Eigen::Vector3d normal_C(0.0, -std::cos(tilt), -std::sin(tilt));  // up, in the optical frame (y down)
  const Eigen::Vector3d p_C(0.3, 0.2, 1.8);
  Eigen::Isometry3d X_CE = Eigen::Isometry3d::Identity();
  X_CE.linear() = Eigen::AngleAxisd(35.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  X_CE.translation() = Eigen::Vector3d(-0.45, 0.0, 0.1);
  Vector6d sigmas;
  sigmas << 0.03, 0.01, 0.02, 0.02, 0.01, 0.015;  // anisotropic, as a registration leaves it
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() = sigmas.cwiseProduct(sigmas);
  const PoseUncertainty u(covariance, X_CE);
  const Eigen::Vector3d p_E = X_CE.inverse() * p_C;
  const Sampled s = Sample(sigmas, X_CE, p_C, normal_C);
  const Motion A_C = PoseUncertainty::InCurrent(p_C), A_E = u.InEarlier(p_C);
  EXPECT_NEAR(u.Pixels(A_C, p_C, kK), s.current_px, 0.05 * s.current_px);
  EXPECT_NEAR(u.Z(A_C), s.current_z, 0.05 * s.current_z);
  EXPECT_NEAR(u.Pixels(A_E, p_E, kK), s.earlier_px, 0.05 * s.earlier_px);
  EXPECT_NEAR(u.Z(A_E), s.earlier_z, 0.05 * s.earlier_z);
  // The plane's image slope at the pixel [m per px]: d(depth)/du = z * (n_x / fx) / -(n . ray) ...
  const Eigen::Vector3d ray = p_C / p_C.z();
  const double denom = normal_C.dot(ray);
  const double du = -p_C.z() * normal_C.x() / kK.fx / denom, dv = -p_C.z() * normal_C.y() / kK.fy / denom;
  EXPECT_NEAR(u.Slanted(A_C, p_C, kK, du, dv), s.slanted, 0.08 * s.slanted);
  // On the slanted table the depth under a pixel is much less certain than the point's z.
  EXPECT_GT(s.slanted, 1.5 * s.current_z);
}

TEST(MergeToleranceTest, MotionWithinAPlaneLeavesItsDepthUnchanged) {
  // A floor 1.3 m below the camera: sliding along it changes nothing under a pixel, lifting it does.
  const Eigen::Vector3d p_C(0.1, 1.3, 3.0);  // y down: the floor at y = 1.3
  Matrix6d slide = Matrix6d::Zero();
  slide(0, 0) = slide(2, 2) = 0.04 * 0.04;  // x and z: within the floor plane
  Matrix6d lift = Matrix6d::Zero();
  lift(1, 1) = 0.04 * 0.04;
  const double dv = -3.0 * 3.0 / (kK.fy * 1.3);  // d(depth)/dv of the plane y = 1.3: -z^2 / (fy * h)
  const Motion A = PoseUncertainty::InCurrent(p_C);
  EXPECT_LT(PoseUncertainty(slide, Eigen::Isometry3d::Identity()).Slanted(A, p_C, kK, 0.0, dv), 0.002);
  EXPECT_GT(PoseUncertainty(lift, Eigen::Isometry3d::Identity()).Slanted(A, p_C, kK, 0.0, dv), 0.04);
  EXPECT_GT(PoseUncertainty(slide, Eigen::Isometry3d::Identity()).Pixels(A, p_C, kK), 5.0);
}

}  // namespace
}  // namespace anchordb::engine
