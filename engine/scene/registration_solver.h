#pragma once
// The point-to-plane MAP solver behind AlignIcp (registration.h), free of PCL: registration.cc finds the
// correspondences (kd-tree nearest neighbours, PCL's normals); everything here works on plain Eigen pairs.
//
// Motion: a small motion xi = [t, w] (m, rad; ROS order) acts on the left in the target frame: p' = Exp(xi) p.
// A pair's residual is r = n . (p - q) [m] (p: the source point as currently moved, q, n: its target point and unit
// normal); its Jacobian with respect to a left increment is [n, p x n].
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <span>

#include "engine/scene/registration.h"

namespace anchordb::engine::registration_detail {

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct PointPair {
  Eigen::Vector3d p;  // source point, moved by the current estimate (target frame) [m]
  Eigen::Vector3d q;  // its nearest target point [m]
  Eigen::Vector3d n;  // the target's unit normal at q
  double sigma_m = 0.0;  // standard deviation of the residual n . (p - q) from the noise model [m]
};

// Axial depth noise of a structured-light sensor at depth z [m]: 0.0012 + 0.0019 (z - 0.4)^2 (Nguyen, Izadi,
// Lovell 2012), the model sim/renderer.h draws from.
double SensorSigmaM(double z_m);

// Huber weight of a normalised residual u = r / sigma with threshold k (1 inside, k / |u| outside).
double HuberWeight(double u, double k);
// Huber cost of u (u^2 / 2 inside, k |u| - k^2 / 2 outside).
double HuberCost(double u, double k);

// The data's normal equations: H = sum w J^T J / sigma^2 / inflation, g = sum w J^T r / sigma^2 / inflation, with
// Huber weights w; `inflation` (>= 1) divides the information by the number of residuals that are not
// independent of each other (see CorrelationInflation).
struct NormalEquations {
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double cost = 0.0;             // sum of Huber costs (before the inflation)
  double chi2 = 0.0;             // sum w u^2 (before the inflation)
  double weight_sum = 0.0;       // sum w
  std::size_t pairs = 0;
  double huber_k = 1.5;          // the Huber threshold the weights were computed with
  double information_scale = 1.0;  // 1 / inflation: the factor H and g were scaled by
};
NormalEquations Accumulate(std::span<const PointPair> pairs, double huber_k, double inflation);

// How many residuals share one independent error: the errors of a registration (normals, voxel centroids, the
// parts of a surface each view sees) are correlated over patches of about `patch_m`; the pairs per occupied patch
// (at least 1).
double CorrelationInflation(std::span<const PointPair> pairs, double patch_m);

// The prior in whitened coordinates: xi = S z, z ~ N(0, I). A (numerically) singular prior keeps a floor of
// 1e-12 on its eigenvalues (a zero variance is a motion that is known exactly).
struct PriorWhitening {
  Matrix6d S = Matrix6d::Identity();      // covariance^(1/2)
  Matrix6d S_inv = Matrix6d::Identity();  // covariance^(-1/2)
  Matrix6d information = Matrix6d::Identity();
};
PriorWhitening Whiten(const Matrix6d& prior_covariance);

// The information along a motion u (target frame) from the pairs whose normal sees it: a pair counts only when its
// normal makes a cosine of at least min_alignment with the displacement u moves its point by (d = u_t + u_r x p).
// The noise of estimated normals (a few degrees) gives every point of a plane a tiny component along the plane's
// own directions; summed over thousands of points it looks like information that grows with the point count, not
// with the geometry. Counting only the pairs whose surface really faces the motion removes it. Same scaling (Huber
// weights, 1 / sigma^2, inflation) as `data`.
double GeometricInformation(std::span<const PointPair> pairs, const NormalEquations& data, const Vector6d& u,
                            double min_alignment);

// One Gauss-Newton step of the MAP problem  min 1/2 |S^-1 xi|^2 + data, from the current motion xi_current.
// The data's information relative to the prior's is M = S H S = V diag(lambda) V^T. Along an eigen-direction v
// whose geometric information (GeometricInformation of S v, in the same whitened units as lambda) is below
// min_relative_information the data says less than the prior knows, and the step returns that component of the
// motion to the prior (zero) instead of following the data there.
struct MapStep {
  Vector6d delta = Vector6d::Zero();  // left increment
  std::array<double, 6> relative_information{};  // lambda, ascending
  std::array<double, 6> geometric_information{};  // of the same directions, from the pairs that face them
  std::array<bool, 6> observable{};               // per direction: geometric information >= the bound
  Matrix6d directions = Matrix6d::Identity();     // V, columns in whitened coordinates
  int unobservable = 0;                           // directions that are not observable
};
MapStep SolveMapStep(const NormalEquations& data, std::span<const PointPair> pairs, const PriorWhitening& prior,
                     const Vector6d& xi_current, double min_relative_information, double min_alignment);

// The posterior covariance of the motion (target frame): S (V diag(1 / (1 + lambda)) V^T) S with the eigenvalues of
// the unobservable directions set to 0 (those directions keep the prior's uncertainty), plus `floor`.
Matrix6d PosteriorCovariance(const MapStep& step, const PriorWhitening& prior, const Matrix6d& floor);

// Left exponential / logarithm between motions xi and rigid transforms (SE(3)).
Eigen::Isometry3d ExpMotion(const Vector6d& xi);
Vector6d LogMotion(const Eigen::Isometry3d& X);

}  // namespace anchordb::engine::registration_detail
