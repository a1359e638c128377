// The engine's only PCL translation unit for registration (PCL headers are slow to compile; they stay here).
#include "engine/scene/registration.h"

#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

namespace anchordb::engine {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr ToDownsampledCloud(const std::vector<Eigen::Vector3f>& points, const IcpParams& p) {
  auto raw = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  raw->reserve(points.size());
  const float max_sq = static_cast<float>(p.max_range_m * p.max_range_m);
  for (const auto& q : points) {
    if (q.squaredNorm() <= max_sq) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  auto voxel = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(raw);
  grid.setLeafSize(static_cast<float>(p.voxel_m), static_cast<float>(p.voxel_m), static_cast<float>(p.voxel_m));
  grid.filter(*voxel);
  if (static_cast<int>(voxel->size()) <= p.max_points) return voxel;
  auto even = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  const double step = static_cast<double>(voxel->size()) / p.max_points;
  for (int i = 0; i < p.max_points; ++i) even->push_back((*voxel)[static_cast<std::size_t>(i * step)]);
  return even;
}

}  // namespace

IcpResult AlignIcp(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                   const IcpParams& params) {
  IcpResult result;
  const auto src = ToDownsampledCloud(source, params);
  const auto tgt = ToDownsampledCloud(target, params);
  result.source_points = src->size();
  result.target_points = tgt->size();
  if (src->size() < 10 || tgt->size() < 10) return result;
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(tgt);
  // Mean squared distance to the nearest target point over the source points within the correspondence range,
  // for any candidate transform (PCL's own getFitnessScore compares squared distances with an unsquared range).
  const auto fitness = [&](const Eigen::Matrix4f& T) {
    std::vector<int> index(1);
    std::vector<float> d2(1);
    const double max_d2 = params.max_correspondence_m * params.max_correspondence_m;
    double sum = 0;
    std::size_t n = 0;
    for (const auto& p : *src) {
      const Eigen::Vector4f q = T * Eigen::Vector4f(p.x, p.y, p.z, 1.0f);
      if (tree.nearestKSearch(pcl::PointXYZ(q.x(), q.y(), q.z()), 1, index, d2) > 0 && d2[0] <= max_d2) sum += d2[0], ++n;
    }
    return n ? sum / n : std::numeric_limits<double>::infinity();
  };
  result.fitness_before_m2 = fitness(Eigen::Matrix4f::Identity());
  // Point-to-plane ICP: indoor scenes are mostly planes, along which point-to-point ICP slides. Two passes, the
  // second with a tighter correspondence range, refine the correction.
  const auto with_normals = [&](const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud) {
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
    estimation.setInputCloud(cloud);
    estimation.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    estimation.setKSearch(12);
    pcl::PointCloud<pcl::Normal> normals;
    estimation.compute(normals);
    auto out = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      if (!std::isfinite(normals[i].normal_x)) continue;
      pcl::PointNormal p;
      p.x = (*cloud)[i].x, p.y = (*cloud)[i].y, p.z = (*cloud)[i].z;
      p.normal_x = normals[i].normal_x, p.normal_y = normals[i].normal_y, p.normal_z = normals[i].normal_z;
      out->push_back(p);
    }
    return out;
  };
  const auto src_n = with_normals(src);
  const auto tgt_n = with_normals(tgt);
  Eigen::Matrix4f T = Eigen::Matrix4f::Identity();
  bool converged = src_n->size() >= 10 && tgt_n->size() >= 10;
  for (double range : {params.max_correspondence_m, params.max_correspondence_m / 3.0}) {
    if (!converged) break;
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setInputSource(src_n);
    icp.setInputTarget(tgt_n);
    icp.setMaxCorrespondenceDistance(range);
    icp.setMaximumIterations(params.max_iterations);
    icp.setTransformationEpsilon(params.transformation_epsilon);
    icp.setEuclideanFitnessEpsilon(params.fitness_epsilon);
    pcl::PointCloud<pcl::PointNormal> aligned;
    icp.align(aligned, T);
    converged = icp.hasConverged();
    if (converged) T = icp.getFinalTransformation();
  }
  result.converged = converged;
  result.fitness_m2 = fitness(T);
  result.correction.matrix() = T.cast<double>();
  return result;
}

}  // namespace anchordb::engine
