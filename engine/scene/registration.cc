// The engine's only PCL translation unit for registration (PCL headers are slow to compile; they stay here).
#include "engine/scene/registration.h"

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

namespace anchordb::engine {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr ToDownsampledCloud(const std::vector<Eigen::Vector3f>& points, const IcpParams& p) {
  auto raw = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  raw->reserve(points.size());
  for (const auto& q : points) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
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
  result.fitness_m2 = icp.getFitnessScore(params.max_correspondence_m);
  result.correction.matrix() = icp.getFinalTransformation().cast<double>();
  return result;
}

}  // namespace anchordb::engine
