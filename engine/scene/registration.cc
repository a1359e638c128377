// The engine's only PCL translation unit for registration (PCL headers are slow to compile; they stay here).
#include "engine/scene/registration.h"

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
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setInputSource(src);
  icp.setInputTarget(tgt);
  icp.setMaxCorrespondenceDistance(params.max_correspondence_m);
  icp.setMaximumIterations(params.max_iterations);
  icp.setTransformationEpsilon(params.transformation_epsilon);
  icp.setEuclideanFitnessEpsilon(params.fitness_epsilon);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icp.align(aligned);
  result.converged = icp.hasConverged();
  result.fitness_m2 = fitness(icp.getFinalTransformation());
  result.correction.matrix() = icp.getFinalTransformation().cast<double>();
  return result;
}

}  // namespace anchordb::engine
