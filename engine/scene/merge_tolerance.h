#pragma once
// The remaining pose uncertainty of an earlier model, propagated to a point of the merge (Algorithm 2's per-pixel
// tolerances, issue 13): first-order, X_true = Exp(xi) * X_given with xi ~ N(0, Sigma) (registration.h's Matrix6d,
// [tx ty tz rx ry rz], left perturbation in the current camera frame C of X_C_earlier). A point p (in C, of the
// earlier model as placed there) then moves by dp = [I | -[p]x] xi; its projection and depth follow with the
// pinhole Jacobians. Pure Eigen, header-only; every figure is one sigma (the caller applies its factor k).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "engine/scene/registration.h"
#include "schema/types.h"

namespace anchordb::engine {

using Vector6d = Eigen::Matrix<double, 6, 1>;

using Motion = Eigen::Matrix<double, 3, 6>;  // d(point) / d(xi) [m per unit of xi]

class PoseUncertainty {
 public:
  // `covariance_C`: of X_C_earlier (current camera frame); `X_C_earlier`: the earlier camera in the current one
  // (as the merge uses it, after any applied correction).
  PoseUncertainty(const Matrix6d& covariance_C, const Eigen::Isometry3d& X_C_earlier)
      : sigma_(covariance_C), R_earlier_C_(X_C_earlier.linear().transpose()) {}

  // How a point fixed in the earlier model, at p_C in the current frame, moves there with xi: [I | -[p]x].
  static Motion InCurrent(const Eigen::Vector3d& p) {
    Motion J;
    J << 1, 0, 0, 0, p.z(), -p.y(),  //
        0, 1, 0, -p.z(), 0, p.x(),   //
        0, 0, 1, p.y(), -p.x(), 0;
    return J;
  }
  // How a point fixed in the current frame, at p_C, moves in the earlier camera's frame with xi.
  Motion InEarlier(const Eigen::Vector3d& p_C) const { return -R_earlier_C_ * InCurrent(p_C); }

  // One sigma of the moved point (position p in the frame of `A`, seen by K): along that camera's z [m] and as a
  // radius in its image [px] (sqrt of the trace of the 2x2 covariance).
  double Z(const Motion& A) const { return std::sqrt(std::max(0.0, A.row(2).dot(sigma_ * A.row(2).transpose()))); }
  double Pixels(const Motion& A, const Eigen::Vector3d& p, const PinholeIntrinsics& K) const {
    if (p.z() <= 1e-6) return 0.0;
    Eigen::Matrix<double, 2, 6> P;
    P.row(0) = K.fx / p.z() * (A.row(0) - p.x() / p.z() * A.row(2));
    P.row(1) = K.fy / p.z() * (A.row(1) - p.y() / p.z() * A.row(2));
    return std::sqrt(std::max(0.0, (P * sigma_ * P.transpose()).trace()));
  }
  // One sigma [m] of (the depth a fixed pixel of that image shows of a surface through p with image slope
  // (du_m, dv_m) [m per px]) minus (the point's z), when one of them moves with A: moving sideways over a slanted
  // surface changes the depth under the pixel too; moving within the surface changes nothing (to first order).
  double Slanted(const Motion& A, const Eigen::Vector3d& p, const PinholeIntrinsics& K, double du_m, double dv_m) const {
    if (p.z() <= 1e-6) return 0.0;
    const Vector6d a_u = K.fx / p.z() * (A.row(0) - p.x() / p.z() * A.row(2)).transpose();
    const Vector6d a_v = K.fy / p.z() * (A.row(1) - p.y() / p.z() * A.row(2)).transpose();
    const Vector6d a = A.row(2).transpose() - du_m * a_u - dv_m * a_v;
    return std::sqrt(std::max(0.0, a.dot(sigma_ * a)));
  }

 private:
  Matrix6d sigma_;
  Eigen::Matrix3d R_earlier_C_;
};

}  // namespace anchordb::engine
