// PCL stays inside this translation unit (engine/README.md).
#include "engine/features/extraction.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <Eigen/Eigenvalues>
#include <pcl/console/print.h>
#include <pcl/features/fpfh.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/shot.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "engine/features/features.h"

namespace anchordb::engine {
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

bool Wants(const std::vector<std::string>& types, const char* type) {
  return std::find(types.begin(), types.end(), type) != types.end();
}

template <typename Histogram, int N>
void AddHistograms(const pcl::PointCloud<Histogram>& descriptors, const Cloud& keypoints, const char* type,
                   const float* (*values)(const Histogram&), std::vector<ExtractedFeature>& out) {
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    const float* v = values(descriptors[i]);
    if (!std::all_of(v, v + N, [](float x) { return std::isfinite(x); })) continue;
    if (std::all_of(v, v + N, [](float x) { return x == 0.0f; })) continue;  // no neighbours: PCL leaves zeros
    ExtractedFeature f;
    f.type = type;
    f.descriptor.assign(v, v + N);
    f.anchor_m = keypoints[i].getVector3fMap().cast<double>();
    out.push_back(std::move(f));
  }
}

const float* FpfhValues(const pcl::FPFHSignature33& d) { return d.histogram; }
const float* ShotValues(const pcl::SHOT352& d) { return d.descriptor; }

void AddPlanes(const Cloud::Ptr& cloud, const Eigen::Vector3d& sensor_m, const ExtractionParams& p,
               std::vector<ExtractedFeature>& out) {
  Cloud::Ptr rest = std::make_shared<Cloud>(*cloud);
  const double total = static_cast<double>(cloud->size());
  pcl::SACSegmentation<pcl::PointXYZ> sac;
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setDistanceThreshold(p.plane_distance_m);
  sac.setMaxIterations(200);
  sac.setOptimizeCoefficients(true);
  for (int plane = 0; plane < p.max_planes && static_cast<int>(rest->size()) >= p.min_plane_points; ++plane) {
    pcl::PointIndices inliers;
    pcl::ModelCoefficients model;
    sac.setInputCloud(rest);
    sac.segment(inliers, model);
    if (static_cast<int>(inliers.indices.size()) < p.min_plane_points || model.values.size() != 4) break;
    Eigen::Vector3d n(model.values[0], model.values[1], model.values[2]);
    const double norm = n.norm();
    if (!(norm > 0)) break;
    n /= norm;
    const double d = model.values[3] / norm;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i : inliers.indices) centroid += (*rest)[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
    centroid /= static_cast<double>(inliers.indices.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int i : inliers.indices) {
      const Eigen::Vector3d q = (*rest)[static_cast<std::size_t>(i)].getVector3fMap().cast<double>() - centroid;
      cov += q * q.transpose();
    }
    cov /= static_cast<double>(inliers.indices.size());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const double major = 2.0 * std::sqrt(std::max(0.0, eig.eigenvalues()(2)));
    const double minor = 2.0 * std::sqrt(std::max(0.0, eig.eigenvalues()(1)));
    ExtractedFeature f;
    f.type = "spd";
    f.descriptor = {static_cast<float>(inliers.indices.size() * p.voxel_m * p.voxel_m),
                    static_cast<float>(std::abs(n.z())),
                    static_cast<float>(centroid.z()),
                    static_cast<float>(major),
                    static_cast<float>(minor),
                    static_cast<float>(major > 0 ? minor / major : 0.0),
                    static_cast<float>(inliers.indices.size() / std::max(1.0, total)),
                    static_cast<float>(std::abs(n.dot(sensor_m) + d))};
    f.anchor_m = centroid;
    out.push_back(std::move(f));
    pcl::ExtractIndices<pcl::PointXYZ> extract;
    extract.setInputCloud(rest);
    extract.setIndices(std::make_shared<pcl::PointIndices>(inliers));
    extract.setNegative(true);
    auto next = std::make_shared<Cloud>();
    extract.filter(*next);
    rest = next;
  }
}

}  // namespace

std::vector<ExtractedFeature> ExtractFeatures(const std::vector<Eigen::Vector3f>& points_m,
                                              const Eigen::Vector3d& sensor_origin_m,
                                              const std::vector<std::string>& types, const ExtractionParams& p) {
  // SHOT reports every keypoint without a valid local frame on stderr; those keypoints are skipped (zeros) anyway.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  std::vector<ExtractedFeature> out;
  auto raw = std::make_shared<Cloud>();
  raw->reserve(points_m.size());
  for (const auto& q : points_m) {
    if (q.allFinite()) raw->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  if (raw->size() < 10) return out;
  const Cloud::Ptr cloud = Thin(raw, p.voxel_m);
  if (cloud->size() < 10) return out;
  if (Wants(types, "spd")) AddPlanes(cloud, sensor_origin_m, p, out);
  if (!Wants(types, "fpfh") && !Wants(types, "shot")) return out;

  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(tree);
  ne.setRadiusSearch(p.normal_radius_m);
  ne.setViewPoint(static_cast<float>(sensor_origin_m.x()), static_cast<float>(sensor_origin_m.y()),
                  static_cast<float>(sensor_origin_m.z()));
  ne.compute(*normals);
  // Points whose normal could not be estimated (too few neighbours) would poison the histograms: drop them.
  auto surface = std::make_shared<Cloud>();
  auto surface_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const auto& nrm = (*normals)[i];
    if (std::isfinite(nrm.normal_x) && std::isfinite(nrm.normal_y) && std::isfinite(nrm.normal_z)) {
      surface->push_back((*cloud)[i]);
      surface_normals->push_back(nrm);
    }
  }
  if (surface->size() < 10) return out;
  const Cloud::Ptr keypoints = Thin(surface, p.keypoint_voxel_m);
  auto surface_tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  // FPFH and SHOT at the keypoints, over the whole thinned surface; `length` is the descriptor's size.
  const auto describe = [&](auto estimator, auto signature, auto length, const char* type, auto values) {
    using Signature = decltype(signature);
    estimator.setInputCloud(keypoints);
    estimator.setSearchSurface(surface);
    estimator.setInputNormals(surface_normals);
    estimator.setSearchMethod(surface_tree);
    estimator.setRadiusSearch(p.feature_radius_m);
    pcl::PointCloud<Signature> descriptors;
    estimator.compute(descriptors);
    AddHistograms<Signature, decltype(length)::value>(descriptors, *keypoints, type, values, out);
  };
  if (Wants(types, "fpfh")) {
    describe(pcl::FPFHEstimation<pcl::PointXYZ, pcl::Normal, pcl::FPFHSignature33>(), pcl::FPFHSignature33(), std::integral_constant<int, 33>(),
             "fpfh", &FpfhValues);
  }
  if (Wants(types, "shot")) {
    describe(pcl::SHOTEstimation<pcl::PointXYZ, pcl::Normal, pcl::SHOT352>(), pcl::SHOT352(), std::integral_constant<int, 352>(), "shot",
             &ShotValues);
  }
  return out;
}

}  // namespace anchordb::engine
