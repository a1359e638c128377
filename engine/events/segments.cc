// The engine's PCL translation unit for Euclidean clustering (PCL headers are slow to compile; they stay here).
#include "engine/events/segments.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>

namespace anchordb::engine {

std::vector<Segment> ClusterSegments(const std::vector<Eigen::Vector3f>& points_map, const SegmentParams& params) {
  std::vector<Segment> out;
  if (points_map.empty()) return out;
  const std::size_t step = std::max<std::size_t>(1, (points_map.size() + params.max_input_points - 1) /
                                                        static_cast<std::size_t>(std::max(1, params.max_input_points)));
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points_map.size() / step + 1);
  for (std::size_t i = 0; i < points_map.size(); i += step) {
    const auto& p = points_map[i];
    cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  }
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(cloud);
  std::vector<pcl::PointIndices> clusters;
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(params.cluster_tolerance_m);
  extraction.setMinClusterSize(std::max(1, static_cast<int>(params.min_points / static_cast<int>(step))));
  extraction.setMaxClusterSize(std::max(1, static_cast<int>(params.max_points / static_cast<int>(step))));
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(cloud);
  extraction.extract(clusters);
  for (const auto& c : clusters) {
    Segment s;
    s.min_m = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    s.max_m = -s.min_m;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i : c.indices) {
      const auto& q = (*cloud)[static_cast<std::size_t>(i)];
      const Eigen::Vector3d p(q.x, q.y, q.z);
      sum += p;
      s.min_m = s.min_m.cwiseMin(p);
      s.max_m = s.max_m.cwiseMax(p);
    }
    s.centroid_m = sum / static_cast<double>(c.indices.size());
    s.points = static_cast<int>(c.indices.size() * step);
    if (s.Extent().maxCoeff() < params.min_extent_m) continue;
    const std::size_t keep = std::min<std::size_t>(c.indices.size(), static_cast<std::size_t>(params.sample_points));
    const double stride = static_cast<double>(c.indices.size()) / static_cast<double>(std::max<std::size_t>(1, keep));
    for (std::size_t k = 0; k < keep; ++k) {
      const auto& q = (*cloud)[static_cast<std::size_t>(c.indices[static_cast<std::size_t>(k * stride)])];
      s.sample_m.emplace_back(q.x, q.y, q.z);
    }
    out.push_back(std::move(s));
  }
  std::sort(out.begin(), out.end(), [](const Segment& a, const Segment& b) { return a.points > b.points; });
  return out;
}

}  // namespace anchordb::engine
