// The engine's only PCL translation unit for registration (PCL headers are slow to compile; they stay here).
#include "engine/scene/registration.h"

#include "engine/scene/registration_solver.h"

#include <flann/flann.hpp>
#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace anchordb::engine {

struct IcpTargetData {
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud;  // downsampled, with valid normals
  std::vector<float> xyz;                        // its points, N x 3 row-major (the search tree's data set)
  // FLANN's kd-tree (PCL's search backend) over `xyz`, shared by every alignment; queried in batches (one call per
  // correspondence pass: a call per point pays FLANN's per-call set-up each time).
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index;
  double spacing_m = 0.0;  // typical distance between neighbouring target points (voxel, widened by the thinning)
};

namespace {

// Range-limited and thinned evenly to at most max_input_points.
pcl::PointCloud<pcl::PointXYZ>::Ptr Thinned(const std::vector<Eigen::Vector3f>& points, const IcpParams& p) {
  auto raw = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const float max_sq = static_cast<float>(p.max_range_m * p.max_range_m);
  const std::size_t stride = std::max<std::size_t>(
      1, p.max_input_points > 0 ? (points.size() + p.max_input_points - 1) / static_cast<std::size_t>(p.max_input_points) : 1);
  raw->reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const auto& q = points[i];
    if (q.allFinite() && q.squaredNorm() <= max_sq) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  return raw;
}

// Voxel-downsampled, then evenly subsampled to at most max_points; *thinning = voxels per kept point (>= 1).
pcl::PointCloud<pcl::PointXYZ>::Ptr Downsampled(const pcl::PointCloud<pcl::PointXYZ>::Ptr& raw, double voxel_m,
                                                int max_points, double* thinning = nullptr) {
  auto voxel = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  if (raw->empty()) return voxel;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(raw);
  grid.setLeafSize(static_cast<float>(voxel_m), static_cast<float>(voxel_m), static_cast<float>(voxel_m));
  grid.filter(*voxel);
  if (thinning) *thinning = std::max(1.0, static_cast<double>(voxel->size()) / std::max(1, max_points));
  if (static_cast<int>(voxel->size()) <= max_points) return voxel;
  auto even = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const double step = static_cast<double>(voxel->size()) / max_points;
  for (int i = 0; i < max_points; ++i) even->push_back((*voxel)[static_cast<std::size_t>(i * step)]);
  return even;
}

}  // namespace

IcpTarget PrepareIcpTarget(const std::vector<Eigen::Vector3f>& target, const IcpParams& params) {
  IcpTarget out;
  out.params = params;
  double thinning = 1.0;
  const auto tgt = Downsampled(Thinned(target, params), params.voxel_m, params.max_points, &thinning);
  auto data = std::make_shared<IcpTargetData>();
  data->cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  data->spacing_m = params.voxel_m * std::sqrt(thinning);
  if (tgt->size() >= 10) {
    // Normals of the target only: point-to-plane ICP measures the residual along the target's normals.
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
    estimation.setInputCloud(tgt);
    estimation.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    estimation.setKSearch(params.normal_neighbours);
    estimation.setViewPoint(0.0f, 0.0f, 0.0f);  // the current camera: normals face it
    pcl::PointCloud<pcl::Normal> normals;
    estimation.compute(normals);
    data->cloud->reserve(tgt->size());
    for (std::size_t i = 0; i < tgt->size(); ++i) {
      if (!std::isfinite(normals[i].normal_x)) continue;
      pcl::PointNormal p;
      p.x = (*tgt)[i].x, p.y = (*tgt)[i].y, p.z = (*tgt)[i].z;
      p.normal_x = normals[i].normal_x, p.normal_y = normals[i].normal_y, p.normal_z = normals[i].normal_z;
      p.curvature = normals[i].curvature;
      data->cloud->push_back(p);
      data->xyz.insert(data->xyz.end(), {p.x, p.y, p.z});
    }
  }
  if (!data->cloud->empty()) {
    data->index = std::make_unique<flann::Index<flann::L2_Simple<float>>>(
        flann::Matrix<float>(data->xyz.data(), data->cloud->size(), 3), flann::KDTreeSingleIndexParams(15));
    data->index->buildIndex();
  }
  out.points = data->cloud->size();
  out.data = std::move(data);
  return out;
}

namespace {

using namespace registration_detail;

// The source at one level of the coarse-to-fine schedule.
struct Level {
  std::vector<Eigen::Vector3d> points;
  double voxel_m = 0.0;
  double range_m = 0.0;
};

std::vector<Eigen::Vector3d> ToEigen(const pcl::PointCloud<pcl::PointXYZ>& cloud) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) out.emplace_back(p.x, p.y, p.z);
  return out;
}

// The fit of a pose: the share of source points that agree with the target (their nearest target point within the
// finest correspondence range, their point-to-plane distance within 3 sigma of the noise model), and the report's
// fitness (mean squared point distance within the fitness range).
struct Fit {
  double agreement = 0.0;
  double fitness_m2 = std::numeric_limits<double>::infinity();
};

class Aligner {
 public:
  Aligner(const IcpTargetData& target, const IcpParams& params, const PriorWhitening& prior)
      : tgt_(target), params_(params), prior_(prior) {}

  // The nearest target point of every point of `src` moved by X (squared distance, index; -1 when none).
  void Nearest(const std::vector<Eigen::Vector3d>& src, const Eigen::Isometry3d& X) const {
    query_.resize(src.size() * 3);
    moved_.resize(src.size());
    for (std::size_t i = 0; i < src.size(); ++i) {
      moved_[i] = X * src[i];
      const bool finite = moved_[i].allFinite();
      for (int k = 0; k < 3; ++k) query_[3 * i + k] = finite ? static_cast<float>(moved_[i](k)) : 1e30f;
    }
    index_.assign(src.size(), -1);
    d2_.assign(src.size(), std::numeric_limits<float>::infinity());
    if (src.empty()) return;
    flann::Matrix<float> queries(query_.data(), src.size(), 3), dists(d2_.data(), src.size(), 1);
    flann::Matrix<int> indices(index_.data(), src.size(), 1);
    tgt_.index->knnSearch(queries, indices, dists, 1, flann::SearchParams(-1, 0.0f, false));
  }

  // The point-to-plane pairs of `src` moved by X whose nearest target point lies within range_m, and not so far
  // to its side that it lies past a surface's edge (the nearest point of a surface beyond its boundary says
  // nothing about the motion along it).
  void Match(const std::vector<Eigen::Vector3d>& src, const Eigen::Isometry3d& X, double range_m, double voxel_m,
             std::vector<PointPair>& pairs) const {
    pairs.clear();
    Nearest(src, X);
    const double max_d2 = range_m * range_m;
    const double max_side_m = params_.max_side_spacings * std::max(tgt_.spacing_m, voxel_m);
    const double voxel_var = 0.15 * voxel_m * 0.15 * voxel_m;  // a voxel centroid's offset from the surface
    for (std::size_t i = 0; i < src.size(); ++i) {
      if (index_[i] < 0 || !(d2_[i] <= max_d2)) continue;
      const auto& t = (*tgt_.cloud)[static_cast<std::size_t>(index_[i])];
      const Eigen::Vector3d q(t.x, t.y, t.z), n(t.normal_x, t.normal_y, t.normal_z);
      const Eigen::Vector3d& p = moved_[i];
      const double along = n.dot(p - q);
      if ((p - q - along * n).norm() > max_side_m) continue;
      const double sq = SensorSigmaM(t.z), sp = SensorSigmaM(p.z());
      pairs.push_back({p, q, n, std::sqrt(sq * sq + sp * sp + voxel_var)});
    }
  }

  Fit Evaluate(const std::vector<Eigen::Vector3d>& src, const Eigen::Isometry3d& X) const {
    Nearest(src, X);
    Fit fit;
    double sum = 0;
    std::size_t n = 0, agree = 0;
    const double fitness_d2 = params_.max_correspondence_m * params_.max_correspondence_m;
    const double agree_d2 = params_.min_correspondence_m * params_.min_correspondence_m;
    for (std::size_t i = 0; i < src.size(); ++i) {
      if (index_[i] < 0 || !(d2_[i] <= fitness_d2)) continue;
      sum += d2_[i], ++n;
      const auto& t = (*tgt_.cloud)[static_cast<std::size_t>(index_[i])];
      const double r = Eigen::Vector3d(t.normal_x, t.normal_y, t.normal_z).dot(moved_[i] - Eigen::Vector3d(t.x, t.y, t.z));
      const double sigma = std::hypot(SensorSigmaM(t.z), SensorSigmaM(moved_[i].z()));
      agree += d2_[i] <= agree_d2 && std::abs(r) <= 3.0 * sigma;
    }
    if (n) fit.fitness_m2 = sum / n;
    fit.agreement = src.empty() ? 0.0 : static_cast<double>(agree) / src.size();
    return fit;
  }

  NormalEquations Equations(const std::vector<PointPair>& pairs, double residual_scale2 = 1.0) const {
    const double inflation = CorrelationInflation(pairs, params_.correlation_patch_m) * std::max(1.0, residual_scale2);
    return Accumulate(pairs, params_.huber_k, inflation);
  }

  // MAP cost of X at a level: the data's Huber cost (an unmatched point costs as much as one at the range), per
  // independent patch, plus the prior's.
  double Cost(const Level& level, const Eigen::Isometry3d& X) const {
    Match(level.points, X, level.range_m, level.voxel_m, pairs_);
    if (pairs_.empty()) return std::numeric_limits<double>::infinity();
    const NormalEquations ne = Equations(pairs_);
    double sigma = 0;
    for (const auto& pp : pairs_) sigma += pp.sigma_m;
    sigma /= pairs_.size();
    const double inflation = CorrelationInflation(pairs_, params_.correlation_patch_m);
    const double unmatched = static_cast<double>(level.points.size() - pairs_.size());
    const Vector6d z = prior_.S_inv * LogMotion(X);
    return (ne.cost + unmatched * HuberCost(level.range_m / sigma, params_.huber_k)) / inflation + 0.5 * z.squaredNorm();
  }

  // Gauss-Newton MAP steps at one level from X; false if the pose became non-finite or nothing matched.
  bool Refine(const Level& level, int max_iterations, Eigen::Isometry3d& X, int& iterations) const {
    for (int it = 0; it < max_iterations; ++it) {
      Match(level.points, X, level.range_m, level.voxel_m, pairs_);
      if (pairs_.size() < 6) return false;
      const MapStep step = SolveMapStep(Equations(pairs_), pairs_, prior_, LogMotion(X), params_.min_relative_information,
                                        params_.min_normal_alignment);
      ++iterations;
      if (!step.delta.allFinite()) return false;
      X = ExpMotion(step.delta) * X;
      if (step.delta.head<3>().norm() + step.delta.tail<3>().norm() < params_.step_epsilon) break;
    }
    return X.matrix().allFinite();
  }

  std::vector<PointPair>& pairs() const { return pairs_; }

 private:
  const IcpTargetData& tgt_;
  const IcpParams& params_;
  const PriorWhitening& prior_;
  mutable std::vector<PointPair> pairs_;
  mutable std::vector<float> query_, d2_;
  mutable std::vector<int> index_;
  mutable std::vector<Eigen::Vector3d> moved_;
};

std::string Format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, a, b, c, d);
  return buffer;
}

}  // namespace

IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target) {
  return AlignIcp(source, target,
                  PoseCovarianceFromSigma(target.params.prior_sigma_translation_m * std::sqrt(2.0),
                                          target.params.prior_sigma_rotation_rad * std::sqrt(2.0)));
}

IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const IcpTarget& target,
                   const Matrix6d& prior_covariance) {
  const IcpParams& params = target.params;
  IcpResult result;
  result.covariance = prior_covariance;
  result.verdict = "not enough points";
  const auto raw = Thinned(source, params);
  // The coarse-to-fine schedule: the source at each level's voxel size, shrinking correspondence ranges.
  std::vector<Level> levels;
  double range = params.coarse_correspondence_m;
  for (std::size_t l = 0; l < params.level_voxel_m.size(); ++l) {
    Level level;
    level.voxel_m = std::max(params.level_voxel_m[l], params.voxel_m);
    level.points = ToEigen(*Downsampled(raw, level.voxel_m, params.level_max_points[l]));
    level.range_m = std::max(range, params.min_correspondence_m);
    range *= 0.5;
    levels.push_back(std::move(level));
  }
  const std::vector<Eigen::Vector3d>& fine = levels.back().points;
  result.source_points = fine.size();
  result.target_points = target.points;
  if (fine.size() < 10 || target.points < 10 || !target.data || !target.data->index) return result;
  if (!prior_covariance.allFinite()) {
    result.verdict = "non-finite prior covariance";
    return result;
  }
  const PriorWhitening prior = Whiten(prior_covariance);
  const Aligner aligner(*target.data, params, prior);
  const Fit before = aligner.Evaluate(fine, Eigen::Isometry3d::Identity());
  result.fitness_before_m2 = before.fitness_m2;

  // Multi-start at the coarse level: the prior pose and +-start_sigmas along the prior's widest translations.
  std::vector<Eigen::Isometry3d> starts = {Eigen::Isometry3d::Identity()};
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(prior_covariance.topLeftCorner<3, 3>());
    for (int k = 0; k < std::min(params.extra_start_directions, 3); ++k) {
      const Eigen::Vector3d t = eig.eigenvectors().col(2 - k) * std::sqrt(std::max(0.0, eig.eigenvalues()(2 - k)));
      for (const double sign : {-1.0, 1.0}) {
        Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
        X.translation() = sign * params.start_sigmas * t;
        starts.push_back(X);
      }
    }
  }
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  double best_cost = std::numeric_limits<double>::infinity();
  bool converged = false;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    Eigen::Isometry3d start = starts[k];
    if (!aligner.Refine(levels.front(), params.level_iterations[0], start, result.iterations)) continue;
    // A start away from the prior pose must explain the data clearly better (else, along a direction the data
    // hardly sees, it would stay where it started).
    const double cost = aligner.Cost(levels.front(), start) + (k == 0 ? 0.0 : params.start_margin);
    if (cost < best_cost) best_cost = cost, X = start, converged = true;
  }
  for (std::size_t l = 1; converged && l < levels.size(); ++l) converged = aligner.Refine(levels[l], params.level_iterations[l], X, result.iterations);

  // Conditioning and the posterior at the final pose: the information is deflated by the residuals' own scale
  // when they are larger than the noise model says.
  std::vector<PointPair>& pairs = aligner.pairs();
  if (converged) aligner.Match(fine, X, levels.back().range_m, levels.back().voxel_m, pairs);
  converged = converged && pairs.size() >= 6;
  result.converged = converged;
  if (!converged) {
    result.verdict = "did not converge";
    return result;
  }
  result.correction = X;
  result.inlier_fraction = static_cast<double>(pairs.size()) / fine.size();
  double sq = 0;
  for (const auto& pp : pairs) sq += std::pow(pp.n.dot(pp.p - pp.q), 2);
  result.residual_rms_m = std::sqrt(sq / pairs.size());
  const NormalEquations unscaled = aligner.Equations(pairs);
  const double scale2 = unscaled.weight_sum > 6 ? unscaled.chi2 / (unscaled.weight_sum - 6) : 1.0;
  const Vector6d xi = LogMotion(X);
  const MapStep step = SolveMapStep(aligner.Equations(pairs, scale2), pairs, prior, xi, params.min_relative_information,
                                     params.min_normal_alignment);
  result.relative_information = step.relative_information;
  result.unobservable_directions = step.unobservable;
  result.mahalanobis2 = xi.dot(prior.information * xi);
  const Fit after = aligner.Evaluate(fine, X);
  result.fitness_m2 = after.fitness_m2;

  const double angle_deg = Eigen::AngleAxisd(X.linear()).angle() * 180.0 / 3.14159265358979;
  const std::string proposed = Format("correction %.1f cm / %.2f deg", X.translation().norm() * 100, angle_deg);
  if (result.inlier_fraction < params.min_inlier_fraction) {
    result.verdict = Format("rejected: too little overlap, %.0f %% of the source matched (at least %.0f %%); ",
                            100 * result.inlier_fraction, 100 * params.min_inlier_fraction) + proposed;
  } else if (!(after.agreement >= before.agreement * (1.0 - params.fit_tolerance))) {
    result.verdict = Format("rejected: a worse fit, %.0f %% -> %.0f %% of the source agreeing; ", 100 * before.agreement,
                            100 * after.agreement) + proposed;
  } else if (!(result.mahalanobis2 <= params.max_mahalanobis2)) {
    result.verdict = Format("rejected: inconsistent with the prior, squared Mahalanobis distance %.1f > %.2f; ",
                            result.mahalanobis2, params.max_mahalanobis2) + proposed;
  } else {
    result.accepted = true;
    result.covariance = PosteriorCovariance(
        step, prior, PoseCovarianceFromSigma(params.floor_sigma_translation_m, params.floor_sigma_rotation_rad));
    result.verdict = Format("accepted: %.0f %% -> %.0f %% of the source agreeing, %.1f mm rms, squared Mahalanobis "
                            "distance %.1f; ", 100 * before.agreement, 100 * after.agreement,
                            1e3 * result.residual_rms_m, result.mahalanobis2) + proposed +
                     Format("; %.0f of 6 directions unobservable (kept at the prior)", step.unobservable);
  }
  return result;
}

IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params) {
  return AlignIcp(source, PrepareIcpTarget(target, params));
}

}  // namespace anchordb::engine
