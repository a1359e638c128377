// The engine's only PCL translation unit for registration (PCL headers are slow to compile; they stay here).
#include "engine/scene/registration.h"

#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace anchordb::engine {

struct IcpTargetData {
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud;       // downsampled, with valid normals
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree;    // over `cloud` (x, y, z), shared by every alignment
};

namespace {

// Whether point-to-plane ICP against `target` is singular: the 6x6 normal equations sum [(p - c) x n, n] over the
// target's points; a zero eigenvalue (relative to the largest) is a motion no correspondence can observe (one plane:
// in-plane translation and rotation about its normal). PCL's solver inverts that matrix and returns NaN then.
bool PointToPlaneIsSingular(const pcl::PointCloud<pcl::PointNormal>& target) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (const auto& p : target) {
    if (!std::isfinite(p.normal_x)) continue;
    c += Eigen::Vector3d(p.x, p.y, p.z), ++n;
  }
  if (n < 6) return true;
  c /= static_cast<double>(n);
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  for (const auto& p : target) {
    if (!std::isfinite(p.normal_x)) continue;
    const Eigen::Vector3d normal(p.normal_x, p.normal_y, p.normal_z);
    Eigen::Matrix<double, 6, 1> row;
    row << (Eigen::Vector3d(p.x, p.y, p.z) - c).cross(normal), normal;
    A += row * row.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(A);
  const auto& ev = eig.eigenvalues();  // ascending
  return !(ev(5) > 0.0) || ev(0) <= 1e-9 * ev(5);
}


// Range-limited, thinned to at most max_input_points, voxel-downsampled, then evenly subsampled to max_points.
pcl::PointCloud<pcl::PointXYZ>::Ptr ToDownsampledCloud(const std::vector<Eigen::Vector3f>& points, const IcpParams& p,
                                                       int max_points) {
  auto raw = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const float max_sq = static_cast<float>(p.max_range_m * p.max_range_m);
  const std::size_t stride =
      p.max_input_points > 0 ? (points.size() + p.max_input_points - 1) / static_cast<std::size_t>(p.max_input_points) : 1;
  raw->reserve(points.size() / std::max<std::size_t>(stride, 1) + 1);
  for (std::size_t i = 0; i < points.size(); i += std::max<std::size_t>(stride, 1)) {
    const auto& q = points[i];
    if (q.squaredNorm() <= max_sq) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  auto voxel = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(raw);
  grid.setLeafSize(static_cast<float>(p.voxel_m), static_cast<float>(p.voxel_m), static_cast<float>(p.voxel_m));
  grid.filter(*voxel);
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
  const auto tgt = ToDownsampledCloud(target, params, params.max_points);
  auto data = std::make_shared<IcpTargetData>();
  data->cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  if (tgt->size() >= 10) {
    // Normals of the target only: point-to-plane ICP measures the residual along the target's normals.
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
    estimation.setInputCloud(tgt);
    estimation.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    estimation.setKSearch(12);
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
    }
  }
  data->tree = std::make_shared<pcl::search::KdTree<pcl::PointNormal>>();
  if (!data->cloud->empty()) data->tree->setInputCloud(data->cloud);
  out.points = data->cloud->size();
  out.data = std::move(data);
  return out;
}

Matrix6d PoseCovarianceFromSigma(double sigma_translation_m, double sigma_rotation_rad) {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << Eigen::Vector3d::Constant(sigma_translation_m * sigma_translation_m),
      Eigen::Vector3d::Constant(sigma_rotation_rad * sigma_rotation_rad);
  return c;
}

// Placeholder until issue 13's registration lands: both map-frame covariances rotated into the current camera frame
// and added (the lever arm of a rotation error is ignored).
Matrix6d RelativePoseCovariance(const Eigen::Isometry3d& X_MapCurrent, const Matrix6d& covariance_current_map,
                                const Eigen::Isometry3d& X_MapEarlier, const Matrix6d& covariance_earlier_map) {
  (void)X_MapEarlier;
  Matrix6d R = Matrix6d::Zero();
  const Eigen::Matrix3d R_CM = X_MapCurrent.linear().transpose();
  R.topLeftCorner<3, 3>() = R_CM, R.bottomRightCorner<3, 3>() = R_CM;
  return R * (covariance_current_map + covariance_earlier_map) * R.transpose();
}

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
  const auto src_xyz = ToDownsampledCloud(source, params, params.max_source_points);
  result.source_points = src_xyz->size();
  result.target_points = target.points;
  if (src_xyz->size() < 10 || target.points < 10 || !target.data) return result;
  const IcpTargetData& tgt = *target.data;
  if (PointToPlaneIsSingular(*tgt.cloud)) {  // not converged: the prior pose stands
    result.verdict = "singular point-to-plane problem";
    return result;
  }
  // The source needs no normals (point-to-plane uses the target's); zero normals keep PCL's type uniform.
  auto src = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  src->reserve(src_xyz->size());
  for (const auto& q : *src_xyz) {
    pcl::PointNormal p;
    p.x = q.x, p.y = q.y, p.z = q.z;
    p.normal_x = p.normal_y = p.normal_z = 0.0f, p.curvature = 0.0f;
    src->push_back(p);
  }
  // Mean squared distance to the nearest target point over the source points within the correspondence range,
  // for any candidate transform (PCL's own getFitnessScore compares squared distances with an unsquared range).
  const auto fitness = [&](const Eigen::Matrix4f& T) {
    pcl::Indices index(1);
    std::vector<float> d2(1);
    const double max_d2 = params.max_correspondence_m * params.max_correspondence_m;
    double sum = 0;
    std::size_t n = 0;
    pcl::PointNormal q;
    for (const auto& p : *src) {
      const Eigen::Vector4f t = T * Eigen::Vector4f(p.x, p.y, p.z, 1.0f);
      q.x = t.x(), q.y = t.y(), q.z = t.z();
      if (!t.allFinite()) continue;
      if (tgt.tree->nearestKSearch(q, 1, index, d2) > 0 && d2[0] <= max_d2) sum += d2[0], ++n;
    }
    return n ? sum / n : std::numeric_limits<double>::infinity();
  };
  result.fitness_before_m2 = fitness(Eigen::Matrix4f::Identity());
  // Point-to-plane ICP: indoor scenes are mostly planes, along which point-to-point ICP slides. Two passes: a coarse
  // one (a subset of the source, the full correspondence range), then a fine one (all source points, a third of the
  // range). The target's search tree is reused.
  auto coarse = src;
  if (params.coarse_source_points > 0 && static_cast<int>(src->size()) > params.coarse_source_points) {
    coarse = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    const double step = static_cast<double>(src->size()) / params.coarse_source_points;
    for (int i = 0; i < params.coarse_source_points; ++i) coarse->push_back((*src)[static_cast<std::size_t>(i * step)]);
  }
  Eigen::Matrix4f T = Eigen::Matrix4f::Identity();
  bool converged = true;
  for (const bool fine : {false, true}) {
    const double range = fine ? params.max_correspondence_m / 3.0 : params.max_correspondence_m;
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setSearchMethodTarget(tgt.tree, /*force_no_recompute=*/true);
    icp.setInputSource(fine ? src : coarse);
    icp.setInputTarget(tgt.cloud);
    icp.setMaxCorrespondenceDistance(range);
    icp.setMaximumIterations(params.max_iterations);
    icp.setTransformationEpsilon(fine ? params.transformation_epsilon : params.coarse_transformation_epsilon);
    icp.setEuclideanFitnessEpsilon(params.fitness_epsilon);
    pcl::PointCloud<pcl::PointNormal> aligned;
    icp.align(aligned, T);
    converged = icp.hasConverged();
    if (!converged) break;
    // Degenerate geometry (a single plane: singular normal equations) can yield a non-finite transform; the pose is
    // then kept as it was (and nothing non-finite reaches PCL's kd-tree, whose assertion would abort the process).
    const Eigen::Matrix4f next = icp.getFinalTransformation();
    if (!next.allFinite()) {
      converged = false;
      break;
    }
    T = next;
  }
  result.converged = converged;
  result.fitness_m2 = fitness(T);
  result.correction.matrix() = T.cast<double>();
  // Placeholder acceptance until issue 13's registration lands: converged, a better fit, and within fixed bounds.
  const double angle = Eigen::AngleAxisd(result.correction.linear()).angle();
  if (!converged) {
    result.verdict = "did not converge";
  } else if (!(result.fitness_m2 < result.fitness_before_m2)) {
    result.verdict = "no better fit";
  } else if (result.correction.translation().norm() > 0.15 || angle > 0.105) {
    result.verdict = "correction beyond 15 cm / 6 deg";
  } else {
    result.accepted = true;
    result.verdict = "accepted";
    result.covariance = PoseCovarianceFromSigma(0.0025, 0.001);
  }
  return result;
}

IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params) {
  return AlignIcp(source, PrepareIcpTarget(target, params));
}

}  // namespace anchordb::engine
