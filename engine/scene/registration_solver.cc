// The point-to-plane MAP solver and the pose-covariance algebra of registration.h (no PCL here).
#include "engine/scene/registration_solver.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace anchordb::engine {

Matrix6d PoseCovarianceFromSigma(double sigma_translation_m, double sigma_rotation_rad) {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << Eigen::Vector3d::Constant(sigma_translation_m * sigma_translation_m),
      Eigen::Vector3d::Constant(sigma_rotation_rad * sigma_rotation_rad);
  return c;
}

namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// V(w) of SE(3)'s exponential: the translation of Exp([t, w]) is V(w) t.
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = Skew(w);
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * W;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / (theta * theta) * W +
         (theta - std::sin(theta)) / (theta * theta * theta) * W * W;
}

}  // namespace

// Map-frame errors (ROS): the current camera's true pose is (p_c + a_t, Exp(a_r) R_c), the earlier one's
// (p_e + b_t, Exp(b_r) R_e). To first order the relative pose X_CE = X_MC^-1 X_ME is moved on the left (current
// frame) by xi = [R_c^T (b_t - a_t) + R_c^T [d]x b_r, R_c^T (b_r - a_r)] with d = p_e - p_c: the current camera's
// rotation error turns about the current frame's origin, the earlier one's about the earlier camera, a lever arm d.
Matrix6d RelativePoseCovariance(const Eigen::Isometry3d& X_MapCurrent, const Matrix6d& covariance_current_map,
                                const Eigen::Isometry3d& X_MapEarlier, const Matrix6d& covariance_earlier_map) {
  const Eigen::Matrix3d Rt = X_MapCurrent.linear().transpose();
  const Eigen::Vector3d d = X_MapEarlier.translation() - X_MapCurrent.translation();
  Matrix6d A = Matrix6d::Zero(), B = Matrix6d::Zero();
  A.topLeftCorner<3, 3>() = -Rt, A.bottomRightCorner<3, 3>() = -Rt;
  B.topLeftCorner<3, 3>() = Rt, B.topRightCorner<3, 3>() = Rt * Skew(d), B.bottomRightCorner<3, 3>() = Rt;
  const Matrix6d c = A * covariance_current_map * A.transpose() + B * covariance_earlier_map * B.transpose();
  return 0.5 * (c + c.transpose());
}

namespace registration_detail {

double SensorSigmaM(double z_m) { return 0.0012 + 0.0019 * (z_m - 0.4) * (z_m - 0.4); }

double HuberWeight(double u, double k) { return std::abs(u) <= k ? 1.0 : k / std::abs(u); }

double HuberCost(double u, double k) { return std::abs(u) <= k ? 0.5 * u * u : k * std::abs(u) - 0.5 * k * k; }

NormalEquations Accumulate(std::span<const PointPair> pairs, double huber_k, double inflation) {
  NormalEquations out;
  for (const PointPair& pp : pairs) {
    const double r = pp.n.dot(pp.p - pp.q);
    const double u = r / pp.sigma_m;
    const double w = HuberWeight(u, huber_k);
    Vector6d J;
    J << pp.n, pp.p.cross(pp.n);
    const double s = w / (pp.sigma_m * pp.sigma_m);
    out.H.selfadjointView<Eigen::Lower>().rankUpdate(J, s);
    out.g += s * r * J;
    out.cost += HuberCost(u, huber_k);
    out.chi2 += w * u * u;
    out.weight_sum += w;
  }
  out.H = out.H.selfadjointView<Eigen::Lower>();
  out.pairs = pairs.size();
  const double f = 1.0 / std::max(1.0, inflation);
  out.H *= f, out.g *= f;
  out.huber_k = huber_k;
  out.information_scale = f;
  return out;
}

double GeometricInformation(std::span<const PointPair> pairs, const NormalEquations& data, const Vector6d& u,
                            double min_alignment) {
  const Eigen::Vector3d ut = u.head<3>(), ur = u.tail<3>();
  double info = 0.0;
  for (const PointPair& pp : pairs) {
    const Eigen::Vector3d d = ut + ur.cross(pp.p);
    const double along = pp.n.dot(d);  // = J . u
    if (!(std::abs(along) >= min_alignment * d.norm())) continue;
    const double w = HuberWeight(pp.n.dot(pp.p - pp.q) / pp.sigma_m, data.huber_k);
    info += w / (pp.sigma_m * pp.sigma_m) * along * along;
  }
  return info * data.information_scale;
}

double CorrelationInflation(std::span<const PointPair> pairs, double patch_m) {
  if (pairs.empty()) return 1.0;
  std::unordered_set<std::uint64_t> cells;
  for (const PointPair& pp : pairs) {
    const auto c = (pp.q / patch_m).array().floor().cast<std::int64_t>();
    cells.insert(static_cast<std::uint64_t>(c.x() & 0x1FFFFF) | static_cast<std::uint64_t>(c.y() & 0x1FFFFF) << 21 |
                 static_cast<std::uint64_t>(c.z() & 0x1FFFFF) << 42);
  }
  return std::max(1.0, static_cast<double>(pairs.size()) / static_cast<double>(cells.size()));
}

PriorWhitening Whiten(const Matrix6d& prior_covariance) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 * (prior_covariance + prior_covariance.transpose()));
  const Vector6d ev = eig.eigenvalues().cwiseMax(1e-12);
  PriorWhitening w;
  const Matrix6d& V = eig.eigenvectors();
  w.S = V * ev.cwiseSqrt().asDiagonal() * V.transpose();
  w.S_inv = V * ev.cwiseSqrt().cwiseInverse().asDiagonal() * V.transpose();
  w.information = V * ev.cwiseInverse().asDiagonal() * V.transpose();
  return w;
}

MapStep SolveMapStep(const NormalEquations& data, std::span<const PointPair> pairs, const PriorWhitening& prior,
                     const Vector6d& xi_current, double min_relative_information, double min_alignment) {
  MapStep step;
  const Matrix6d M = prior.S * data.H * prior.S;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(0.5 * (M + M.transpose()));
  step.directions = eig.eigenvectors();
  const Vector6d lambda = eig.eigenvalues().cwiseMax(0.0);
  // Whitened: minimise 1/2 |z + y|^2 + 1/2 y^T M y + (S g)^T y over the whitened increment y (xi = S z).
  const Vector6d z = prior.S_inv * xi_current;
  const Vector6d b = step.directions.transpose() * (prior.S * data.g + z);
  const Vector6d zc = step.directions.transpose() * z;
  Vector6d y = Vector6d::Zero();
  for (int k = 0; k < 6; ++k) {
    step.relative_information[k] = lambda(k);
    // Cheap first: a direction whose whole information is under the bound needs no pass over the pairs.
    step.geometric_information[k] =
        lambda(k) < min_relative_information
            ? lambda(k)
            : GeometricInformation(pairs, data, prior.S * step.directions.col(k), min_alignment);
    step.observable[k] = step.geometric_information[k] >= min_relative_information;
    if (!step.observable[k]) {
      ++step.unobservable;
      y(k) = -zc(k);  // back to the prior along this direction
    } else {
      y(k) = -b(k) / (1.0 + lambda(k));
    }
  }
  step.delta = prior.S * (step.directions * y);
  return step;
}

Matrix6d PosteriorCovariance(const MapStep& step, const PriorWhitening& prior, const Matrix6d& floor) {
  Vector6d d;
  for (int k = 0; k < 6; ++k) {
    const double lambda = step.relative_information[k];
    d(k) = step.observable[k] ? 1.0 / (1.0 + lambda) : 1.0;
  }
  const Matrix6d c = prior.S * step.directions * d.asDiagonal() * step.directions.transpose() * prior.S + floor;
  return 0.5 * (c + c.transpose());
}

Eigen::Isometry3d ExpMotion(const Vector6d& xi) {
  const Eigen::Vector3d w = xi.tail<3>();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const double theta = w.norm();
  X.linear() = theta < 1e-12 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
  X.translation() = LeftJacobianSO3(w) * xi.head<3>();
  return X;
}

Vector6d LogMotion(const Eigen::Isometry3d& X) {
  const Eigen::AngleAxisd aa(X.linear());
  const Eigen::Vector3d w = aa.axis() * aa.angle();
  Vector6d xi;
  xi << LeftJacobianSO3(w).inverse() * X.translation(), w;
  return xi;
}

}  // namespace registration_detail
}  // namespace anchordb::engine
