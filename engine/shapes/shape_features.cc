// PCL stays inside this translation unit (engine/README.md).
#include "engine/shapes/shape_features.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_set>

#include <pcl/console/print.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/shot.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

namespace anchordb::engine::shapes_detail {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr Thin(const Cloud::Ptr& in, double voxel_m) {
  auto out = std::make_shared<Cloud>();
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(in);
  grid.setLeafSize(static_cast<float>(voxel_m), static_cast<float>(voxel_m), static_cast<float>(voxel_m));
  grid.filter(*out);
  return out;
}

std::int64_t CellKey(const Eigen::Vector3f& p, double cell_m) {
  const auto c = [&](float v) { return static_cast<std::int64_t>(std::floor(v / cell_m)) & 0x1fffff; };
  return (c(p.x()) << 42) | (c(p.y()) << 21) | c(p.z());
}

}  // namespace

LocalFeatures ComputeLocalFeatures(const std::vector<Eigen::Vector3f>& points_m, const ShapeModelParams& params,
                                   std::uint64_t seed) {
  // SHOT reports every keypoint without a valid local frame on stderr; those keypoints are dropped anyway.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  LocalFeatures out;
  auto raw = std::make_shared<Cloud>();
  raw->reserve(points_m.size());
  for (const auto& q : points_m) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  if (raw->size() < 10) return out;
  const Cloud::Ptr thinned = Thin(raw, params.voxel_m);
  if (thinned->size() < 10) return out;

  // Normals, oriented away from the cloud's centroid: the same rule for a virtual scan in training and for a segment
  // of a map (whose sensor positions are many or unknown), so that SHOT's cosines keep their signs.
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : *thinned) centroid += p.getVector3fMap();
  centroid /= static_cast<float>(thinned->size());
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(thinned);
  ne.setSearchMethod(tree);
  ne.setRadiusSearch(params.normal_radius_m);
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  auto surface = std::make_shared<Cloud>();
  auto surface_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  for (std::size_t i = 0; i < thinned->size(); ++i) {
    pcl::Normal n = normals[i];
    if (!std::isfinite(n.normal_x) || !std::isfinite(n.normal_y) || !std::isfinite(n.normal_z)) continue;
    if (n.getNormalVector3fMap().dot((*thinned)[i].getVector3fMap() - centroid) < 0) {
      n.normal_x = -n.normal_x;
      n.normal_y = -n.normal_y;
      n.normal_z = -n.normal_z;
    }
    surface->push_back((*thinned)[i]);
    surface_normals->push_back(n);
  }
  if (surface->size() < 10) return out;

  // Boundary points: the largest angle between a point's normal and its neighbours' normals (unsigned lines, so a
  // flipped normal is no edge) exceeds the boundary angle.
  auto surface_tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  surface_tree->setInputCloud(surface);
  const float cos_limit = static_cast<float>(std::cos(params.boundary_angle_rad));
  std::vector<char> boundary(surface->size(), 0);
  pcl::Indices neighbours;
  std::vector<float> distances;
  for (std::size_t i = 0; i < surface->size(); ++i) {
    surface_tree->radiusSearch((*surface)[i], params.normal_radius_m, neighbours, distances);
    const Eigen::Vector3f n = (*surface_normals)[i].getNormalVector3fMap();
    for (const auto j : neighbours) {
      if (std::abs(n.dot((*surface_normals)[j].getNormalVector3fMap())) < cos_limit) {
        boundary[i] = 1;
        break;
      }
    }
  }
  // Keypoints: boundary points in a seeded order, one per keypoint voxel; other points fill free voxels only while
  // there are fewer than kMinKeypoints (a sample that is mostly planar).
  constexpr std::size_t kMinKeypoints = 30;
  std::vector<std::size_t> order(surface->size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  std::stable_partition(order.begin(), order.end(), [&](std::size_t i) { return boundary[i] != 0; });
  std::unordered_set<std::int64_t> taken;
  auto keypoints = std::make_shared<Cloud>();
  std::vector<char> keypoint_on_boundary;
  for (const std::size_t i : order) {
    if (static_cast<int>(keypoints->size()) >= params.max_keypoints) break;
    if (!boundary[i] && keypoints->size() >= kMinKeypoints) break;
    if (!taken.insert(CellKey((*surface)[i].getVector3fMap(), params.keypoint_spacing_m)).second) continue;
    keypoints->push_back((*surface)[i]);
    keypoint_on_boundary.push_back(boundary[i]);
  }
  if (keypoints->empty()) return out;

  pcl::SHOTEstimation<pcl::PointXYZ, pcl::Normal, pcl::SHOT352> shot;
  shot.setInputCloud(keypoints);
  shot.setSearchSurface(surface);
  shot.setInputNormals(surface_normals);
  shot.setSearchMethod(surface_tree);
  shot.setRadiusSearch(params.shot_radius_m);
  pcl::PointCloud<pcl::SHOT352> descriptors;
  shot.compute(descriptors);
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    const auto& d = descriptors[i];
    if (!std::all_of(d.descriptor, d.descriptor + kShotDims, [](float x) { return std::isfinite(x); })) continue;
    if (std::all_of(d.descriptor, d.descriptor + kShotDims, [](float x) { return x == 0.0f; })) continue;
    if (!std::all_of(d.rf, d.rf + 9, [](float x) { return std::isfinite(x); })) continue;
    Eigen::Matrix3f frame;
    frame << d.rf[0], d.rf[1], d.rf[2], d.rf[3], d.rf[4], d.rf[5], d.rf[6], d.rf[7], d.rf[8];
    if (std::abs(frame.determinant()) < 0.5f) continue;
    out.positions_m.push_back((*keypoints)[i].getVector3fMap());
    out.frames.push_back(frame);
    out.descriptors.insert(out.descriptors.end(), d.descriptor, d.descriptor + kShotDims);
    out.boundary_keypoints += keypoint_on_boundary[i];
  }
  return out;
}

}  // namespace anchordb::engine::shapes_detail

namespace anchordb::engine {

CloudSize MeasureCloudSize(const std::vector<Eigen::Vector3f>& points_m) {
  CloudSize out;
  if (points_m.empty()) return out;
  const auto span = [](std::vector<float> v, double lo, double hi) {
    const auto at = [&](double q) {
      const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
      return v[k];
    };
    const float a = at(lo);
    return at(hi) - a;
  };
  std::vector<float> z;
  z.reserve(points_m.size());
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points_m) {
    z.push_back(p.z());
    mean += p.head<2>().cast<double>();
  }
  mean /= static_cast<double>(points_m.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : points_m) {
    const Eigen::Vector2d d = p.head<2>().cast<double>() - mean;
    cov += d * d.transpose();
  }
  // The major axis of the horizontal spread (closed form for a symmetric 2 x 2 matrix).
  const double angle = 0.5 * std::atan2(2 * cov(0, 1), cov(0, 0) - cov(1, 1));
  const Eigen::Vector2d major(std::cos(angle), std::sin(angle)), minor(-std::sin(angle), std::cos(angle));
  std::vector<float> a, b;
  a.reserve(points_m.size());
  b.reserve(points_m.size());
  for (const auto& p : points_m) {
    const Eigen::Vector2d d = p.head<2>().cast<double>() - mean;
    a.push_back(static_cast<float>(d.dot(major)));
    b.push_back(static_cast<float>(d.dot(minor)));
  }
  out.height_m = span(std::move(z), 0.01, 0.99);
  const float l = span(std::move(a), 0.02, 0.98), w = span(std::move(b), 0.02, 0.98);
  out.length_m = std::max(l, w);
  out.width_m = std::min(l, w);
  return out;
}

}  // namespace anchordb::engine
