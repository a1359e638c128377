// PCL inside: voxel grid, RANSAC planes, radius outlier removal and Euclidean clustering (thesis 5.3.1).
#include "engine/segmentation/furniture_segmentation.h"

#include <Eigen/Eigenvalues>
#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <Eigen/Geometry>

#include "schema/error.h"

namespace anchordb::engine::segmentation {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

void Check(bool ok, const std::string& name, const std::string& what) {
  if (!ok) throw Error(ErrorCode::kInvalidArgument, name + " " + what, "params." + name);
}

void CheckParams(const SegmentationParams& p) {
  Check(p.voxel_m > 0.001 && p.voxel_m <= 1.0, "voxel_m", "must be in (0.001, 1] m");
  Check(p.plane_distance_m > 0.0 && p.plane_distance_m <= 0.5, "plane_distance_m", "must be in (0, 0.5] m");
  Check(p.plane_iterations >= 1 && p.plane_iterations <= 100000, "plane_iterations", "must be in [1, 100000]");
  Check(p.max_planes >= 0 && p.max_planes <= 100, "max_planes", "must be in [0, 100]");
  Check(p.min_plane_points >= 3, "min_plane_points", "must be at least 3");
  Check(p.axis_tolerance_rad >= 0.0 && p.axis_tolerance_rad < 0.7, "axis_tolerance_rad", "must be in [0, 0.7) rad");
  Check(p.behind_margin_m >= 0.0 && p.behind_margin_m <= 2.0, "behind_margin_m", "must be in [0, 2] m");
  Check(p.max_behind_fraction >= 0.0 && p.max_behind_fraction < 1.0, "max_behind_fraction", "must be in [0, 1)");
  Check(p.wall_min_width_m >= 0.0 && p.wall_min_height_m >= 0.0, "wall_min_width_m", "and wall_min_height_m must not be negative");
  Check(p.band_m >= 0.0 && p.band_m <= 0.5, "band_m", "must be in [0, 0.5] m");
  Check(p.outlier_radius_m >= 0.0 && p.outlier_radius_m <= 1.0, "outlier_radius_m", "must be in [0, 1] m");
  Check(p.outlier_min_neighbours >= 0 && p.outlier_min_neighbours <= 1000, "outlier_min_neighbours", "must be in [0, 1000]");
  Check(p.cluster_tolerance_m > 0.0 && p.cluster_tolerance_m <= 1.0, "cluster_tolerance_m", "must be in (0, 1] m");
  Check(p.core_radius_m > 0.0 && p.core_radius_m <= 0.5, "core_radius_m", "must be in (0, 0.5] m");
  Check(p.core_density >= 0.0 && p.core_density < 1.0, "core_density", "must be in [0, 1)");
  Check(p.min_cluster_points >= 1, "min_cluster_points", "must be at least 1");
  Check(p.contact_m >= 0.0 && p.contact_m <= 1.0, "contact_m", "must be in [0, 1] m");
}

double Signed(const Eigen::Vector4d& plane, const pcl::PointXYZ& q) {
  return plane.head<3>().dot(q.getVector3fMap().cast<double>()) + plane[3];
}

// Width (horizontal, within the plane) and height spanned by the largest connected patch of a vertical plane's
// inliers (an infinite plane also takes in coplanar faces of furniture anywhere in the room).
std::pair<double, double> VerticalSpan(const Cloud::Ptr& cloud, const std::vector<int>& inliers, const Eigen::Vector3d& n,
                                       double link_m) {
  pcl::IndicesPtr indices = std::make_shared<std::vector<int>>(inliers);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(cloud, indices);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(link_m);
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree);
  ec.setInputCloud(cloud);
  ec.setIndices(indices);
  std::vector<pcl::PointIndices> patches;
  ec.extract(patches);
  if (patches.empty()) return {0.0, 0.0};
  const Eigen::Vector3d along = Eigen::Vector3d::UnitZ().cross(n).normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, zlo = lo, zhi = -lo;
  for (int i : patches.front().indices) {  // PCL sorts the clusters largest first
    const Eigen::Vector3d q = (*cloud)[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
    lo = std::min(lo, q.dot(along));
    hi = std::max(hi, q.dot(along));
    zlo = std::min(zlo, q.z());
    zhi = std::max(zhi, q.z());
  }
  return {hi - lo, zhi - zlo};
}

constexpr double kFloorCellM = 0.05;

bool Inside(const Footprint& f, const Eigen::Vector2d& q) {
  const Eigen::Vector2d local = Eigen::Rotation2Dd(-f.yaw_rad) * (q - f.centre_m);
  return std::abs(local.x()) <= 0.5 * f.extent_m.x() && std::abs(local.y()) <= 0.5 * f.extent_m.y();
}

struct Cluster {
  std::vector<int> indices;  // into the remaining cloud
  Eigen::Vector3d lo, hi, centroid;
  bool floor = false, wall = false;
  int merged = 0;
  bool alive = true;
};

void Bounds(const Cloud& cloud, Cluster& c) {
  c.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  c.hi = -c.lo;
  c.centroid.setZero();
  for (int i : c.indices) {
    const Eigen::Vector3d q = cloud[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
    c.lo = c.lo.cwiseMin(q);
    c.hi = c.hi.cwiseMax(q);
    c.centroid += q;
  }
  c.centroid /= static_cast<double>(c.indices.size());
}

// One Euclidean cluster cut at bridges of sparse points (flying pixels trailing from one piece to the next). A
// point is core when its neighbours within core_radius_m number at least core_density times the cluster's median;
// the core points are clustered again, and when two or more core clusters of min_cluster_points come out, every
// other point joins the one whose core point is nearest. Otherwise the cluster stays whole.
std::vector<std::vector<int>> SplitBridges(const Cloud::Ptr& cloud, std::vector<int> indices, const SegmentationParams& p) {
  std::vector<std::vector<int>> whole;
  if (!(p.core_density > 0.0) || indices.size() < 2 * p.min_cluster_points) {
    whole.push_back(std::move(indices));
    return whole;
  }
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud, std::make_shared<std::vector<int>>(indices));
  std::vector<int> count(indices.size());
  std::vector<int> found;
  std::vector<float> d2;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    count[k] = tree.radiusSearch((*cloud)[static_cast<std::size_t>(indices[k])], p.core_radius_m, found, d2);
  }
  std::vector<int> sorted = count;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double threshold = p.core_density * sorted[sorted.size() / 2];
  pcl::IndicesPtr core = std::make_shared<std::vector<int>>();
  for (std::size_t k = 0; k < indices.size(); ++k) {
    if (count[k] >= threshold) core->push_back(indices[k]);
  }
  if (core->size() < 2 * p.min_cluster_points) {
    whole.push_back(std::move(indices));
    return whole;
  }
  pcl::search::KdTree<pcl::PointXYZ>::Ptr core_tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  core_tree->setInputCloud(cloud, core);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(p.cluster_tolerance_m);
  ec.setMinClusterSize(static_cast<int>(p.min_cluster_points));
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(core_tree);
  ec.setInputCloud(cloud);
  ec.setIndices(core);
  std::vector<pcl::PointIndices> parts;
  ec.extract(parts);
  if (parts.size() < 2) {
    whole.push_back(std::move(indices));
    return whole;
  }
  // Everything that is not in a kept core part goes to the part of its nearest kept core point.
  std::unordered_map<int, std::size_t> part_of;
  pcl::IndicesPtr kept = std::make_shared<std::vector<int>>();
  for (std::size_t k = 0; k < parts.size(); ++k) {
    for (int i : parts[k].indices) part_of.emplace(i, k), kept->push_back(i);
  }
  pcl::search::KdTree<pcl::PointXYZ> kept_tree;
  kept_tree.setInputCloud(cloud, kept);
  std::vector<std::vector<int>> out(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) out[k] = parts[k].indices;
  for (int i : indices) {
    if (part_of.count(i)) continue;
    if (kept_tree.nearestKSearch((*cloud)[static_cast<std::size_t>(i)], 1, found, d2) < 1) continue;
    out[part_of.at(found[0])].push_back(i);
  }
  return out;
}

// The finite points thinned on a voxel grid of voxel_m (input_points and thinned_points of `out` set).
Cloud::Ptr Thinned(const std::vector<Eigen::Vector3f>& cloud_m, double voxel_m, SegmentationResult& out) {
  Cloud::Ptr input = std::make_shared<Cloud>();
  for (const Eigen::Vector3f& q : cloud_m) {
    if (q.allFinite()) input->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  out.input_points = input->size();
  Cloud::Ptr thin = std::make_shared<Cloud>();
  if (input->empty()) return thin;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(input);
  const float leaf = static_cast<float>(voxel_m);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(*thin);
  out.thinned_points = thin->size();
  return thin;
}

// A fitted plane's role from the points on either side of it: a horizontal plane with (almost) nothing below is
// floor, with nothing above ceiling; a vertical one with nothing behind is a wall, and a wide and tall one with
// points behind a wall with an opening; anything else a surface. Orients the normal away from the empty side.
void AssignRole(const Cloud::Ptr& thin, const std::vector<int>& inliers, const SegmentationParams& p, FittedPlane& plane) {
  const double allowed_behind = p.max_behind_fraction * static_cast<double>(thin->size());
  const double cos_tol = std::cos(p.axis_tolerance_rad), sin_tol = std::sin(p.axis_tolerance_rad);
  const double nz = plane.coefficients[2];
  std::size_t pos = 0, neg = 0;
  for (const pcl::PointXYZ& q : *thin) {
    const double s = Signed(plane.coefficients, q);
    if (s > p.behind_margin_m) ++pos;
    else if (s < -p.behind_margin_m) ++neg;
  }
  if (std::abs(nz) >= cos_tol) {  // horizontal: orient the normal up
    if (nz < 0) plane.coefficients = -plane.coefficients, std::swap(pos, neg);
    if (static_cast<double>(neg) <= allowed_behind) plane.role = PlaneRole::kFloor, plane.behind = neg;
    else if (static_cast<double>(pos) <= allowed_behind) plane.role = PlaneRole::kCeiling, plane.behind = pos, plane.coefficients = -plane.coefficients;
  } else if (std::abs(nz) <= sin_tol) {  // vertical: the normal points to the side with more points
    if (neg > pos) plane.coefficients = -plane.coefficients, std::swap(pos, neg);
    plane.behind = neg;
    if (static_cast<double>(neg) <= allowed_behind) {
      plane.role = PlaneRole::kWall;
    } else {
      const auto [width, height] = VerticalSpan(thin, inliers, plane.coefficients.head<3>(), 3.0 * p.voxel_m);
      if (width >= p.wall_min_width_m && height >= p.wall_min_height_m) plane.role = PlaneRole::kWallWithOpening;
    }
  }
}

// Step 1: planes, one after another, on what the earlier planes left (out.planes, out.floor_z_m). Answers, for each
// thinned point, the plane that took it (-1: none).
std::vector<int> FitPlanes(const Cloud::Ptr& thin, const SegmentationParams& p, SegmentationResult& out) {
  const std::size_t n = thin->size();
  std::vector<char> in_plane(n, 0);  // taken by an earlier plane (not offered to RANSAC again)
  std::vector<int> plane_of(n, -1);
  std::vector<int> offered(n);
  for (std::size_t i = 0; i < n; ++i) offered[i] = static_cast<int>(i);
  pcl::SACSegmentation<pcl::PointXYZ> sac;
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setDistanceThreshold(p.plane_distance_m);
  sac.setMaxIterations(p.plane_iterations);
  sac.setOptimizeCoefficients(true);
  sac.setInputCloud(thin);
  for (int k = 0; k < p.max_planes && offered.size() >= p.min_plane_points; ++k) {
    sac.setIndices(std::make_shared<std::vector<int>>(offered));
    pcl::PointIndices inliers;
    pcl::ModelCoefficients model;
    sac.segment(inliers, model);
    if (inliers.indices.size() < p.min_plane_points || model.values.size() != 4) break;
    Eigen::Vector3d normal(model.values[0], model.values[1], model.values[2]);
    const double norm = normal.norm();
    if (!(norm > 0.0)) break;
    FittedPlane plane;
    plane.coefficients << normal / norm, model.values[3] / norm;
    plane.inliers = inliers.indices.size();
    for (int i : inliers.indices) in_plane[static_cast<std::size_t>(i)] = 1, plane_of[static_cast<std::size_t>(i)] = k;
    std::vector<int> rest;
    for (int i : offered) {
      if (!in_plane[static_cast<std::size_t>(i)]) rest.push_back(i);
    }
    offered.swap(rest);
    AssignRole(thin, inliers.indices, p, plane);
    out.planes.push_back(plane);
  }
  // A second horizontal plane with nothing below it (the floor seen in two patches) is floor as well; the floor is
  // the lowest one.
  for (const FittedPlane& plane : out.planes) {
    if (plane.role == PlaneRole::kFloor && (!out.floor_z_m || -plane.coefficients[3] < *out.floor_z_m)) out.floor_z_m = -plane.coefficients[3];
  }
  return plane_of;
}

std::int64_t FloorCellKey(double x_m, double y_m) {
  return (static_cast<std::int64_t>(std::floor(x_m / kFloorCellM)) << 32) ^
         (static_cast<std::int64_t>(std::floor(y_m / kFloorCellM)) & 0xffffffff);
}

// Where the floor was seen, in cells of kFloorCellM: a piece may extend back to a wall only over floor nobody saw.
std::unordered_set<std::int64_t> FloorSeen(const Cloud& thin, const std::vector<int>& plane_of, const std::vector<FittedPlane>& planes) {
  std::unordered_set<std::int64_t> seen;
  for (std::size_t i = 0; i < thin.size(); ++i) {
    if (plane_of[i] >= 0 && planes[static_cast<std::size_t>(plane_of[i])].role == PlaneRole::kFloor) {
      seen.insert(FloorCellKey(thin[i].x, thin[i].y));
    }
  }
  return seen;
}

// Step 2: the bounding planes removed with their band (and anything below the floor, above a ceiling), then the
// radius outlier removal.
Cloud::Ptr WithoutBoundingPlanes(const Cloud& thin, const std::vector<FittedPlane>& planes, const SegmentationParams& p) {
  Cloud::Ptr remaining = std::make_shared<Cloud>();
  for (const pcl::PointXYZ& q : thin) {
    bool drop = false;
    for (const FittedPlane& plane : planes) {
      if (plane.role == PlaneRole::kSurface) continue;
      const double s = Signed(plane.coefficients, q);
      // A wall with an opening keeps what lies behind it (another room); the other bounding planes have nothing
      // behind them but noise.
      drop = plane.role == PlaneRole::kWallWithOpening ? std::abs(s) < p.band_m : s < p.band_m;
      if (drop) break;
    }
    if (!drop) remaining->push_back(q);
  }
  if (p.outlier_min_neighbours > 0 && p.outlier_radius_m > 0.0 && !remaining->empty()) {
    pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
    ror.setInputCloud(remaining);
    ror.setRadiusSearch(p.outlier_radius_m);
    ror.setMinNeighborsInRadius(p.outlier_min_neighbours);
    Cloud::Ptr kept = std::make_shared<Cloud>();
    ror.filter(*kept);
    remaining = kept;
  }
  return remaining;
}

// Step 3: Euclidean clusters of min_cluster_points (smaller ones counted), cut at bridges, each marked as resting
// on the floor or touching a wall.
std::vector<Cluster> ClusterPieces(const Cloud::Ptr& remaining, const SegmentationParams& p, SegmentationResult& out) {
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  tree->setInputCloud(remaining);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(p.cluster_tolerance_m);
  ec.setMinClusterSize(1);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(tree);
  ec.setInputCloud(remaining);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  std::vector<std::vector<int>> pieces;
  for (pcl::PointIndices& f : found) {
    if (f.indices.size() < p.min_cluster_points) {
      ++out.small_clusters;
      continue;
    }
    std::vector<std::vector<int>> parts = SplitBridges(remaining, std::move(f.indices), p);
    out.bridges_cut += parts.size() > 1;
    for (auto& part : parts) pieces.push_back(std::move(part));
  }
  std::vector<Cluster> clusters;
  for (std::vector<int>& piece : pieces) {
    Cluster c;
    c.indices = std::move(piece);
    Bounds(*remaining, c);
    c.floor = out.floor_z_m && c.lo.z() <= *out.floor_z_m + p.band_m + p.contact_m;
    for (int i : c.indices) {
      const pcl::PointXYZ& q = (*remaining)[static_cast<std::size_t>(i)];
      for (const FittedPlane& plane : out.planes) {
        if ((plane.role == PlaneRole::kWall || plane.role == PlaneRole::kWallWithOpening) &&
            std::abs(Signed(plane.coefficients, q)) <= p.band_m + p.contact_m) {
          c.wall = true;
          break;
        }
      }
      if (c.wall) break;
    }
    clusters.push_back(std::move(c));
  }
  return clusters;
}

// Step 4: flying clusters into the nearest grounded cluster below them (lowest flying first); those with none below
// are dropped (counted).
void MergeFlying(const Cloud& remaining, double reach_m, std::vector<Cluster>& clusters, SegmentationResult& out) {
  std::vector<std::size_t> flying;
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    if (!clusters[i].floor && !clusters[i].wall) flying.push_back(i);
  }
  std::sort(flying.begin(), flying.end(), [&](std::size_t a, std::size_t b) { return clusters[a].lo.z() < clusters[b].lo.z(); });
  for (std::size_t f : flying) {
    Cluster& fly = clusters[f];
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t g = 0; g < clusters.size(); ++g) {
      const Cluster& ground = clusters[g];
      if (g == f || !ground.alive || !(ground.floor || ground.wall)) continue;
      const bool overlaps = ground.lo.x() <= fly.hi.x() + reach_m && ground.hi.x() >= fly.lo.x() - reach_m &&
                            ground.lo.y() <= fly.hi.y() + reach_m && ground.hi.y() >= fly.lo.y() - reach_m;
      if (!overlaps || ground.lo.z() >= fly.lo.z()) continue;  // not below it
      const double d = (ground.centroid.head<2>() - fly.centroid.head<2>()).norm() + std::max(0.0, fly.lo.z() - ground.hi.z());
      if (d < best_d) best_d = d, best = static_cast<int>(g);
    }
    fly.alive = false;
    if (best < 0) {
      ++out.flying_dropped;
      continue;
    }
    Cluster& into = clusters[static_cast<std::size_t>(best)];
    into.indices.insert(into.indices.end(), fly.indices.begin(), fly.indices.end());
    into.merged += 1 + fly.merged;
    Bounds(remaining, into);
  }
}

// Step 5: parts of one piece that occlusion split apart side by side (a table's far leg, a corner sofa's arm): a
// cluster whose footprint lies for the most part (part_overlap) inside a larger cluster's joins it.
void JoinParts(const Cloud& remaining, double part_overlap, std::vector<Cluster>& clusters) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    if (clusters[i].alive) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return clusters[a].indices.size() < clusters[b].indices.size(); });
  const auto footprint = [&](const Cluster& c) {
    std::vector<Eigen::Vector3f> pts;
    pts.reserve(c.indices.size());
    for (int i : c.indices) pts.push_back(remaining[static_cast<std::size_t>(i)].getVector3fMap());
    return FootprintOf(pts);
  };
  for (std::size_t k = 0; k < order.size(); ++k) {
    Cluster& part = clusters[order[k]];
    const Footprint fp = footprint(part);
    for (std::size_t m = order.size(); m-- > k + 1;) {
      Cluster& whole = clusters[order[m]];
      if (!whole.alive || whole.indices.size() <= part.indices.size()) continue;
      if (FootprintOverlap(fp, footprint(whole)) < part_overlap) continue;
      whole.indices.insert(whole.indices.end(), part.indices.begin(), part.indices.end());
      whole.merged += 1 + part.merged;
      whole.floor |= part.floor;
      whole.wall |= part.wall;
      Bounds(remaining, whole);
      part.alive = false;
      break;
    }
  }
}

// Step 6: a surviving cluster as a segment; its footprint extends back to a wall over floor nobody saw (at most a
// fifth of the strip's floor cells seen).
FurnitureSegment ToSegment(const Cluster& c, const Cloud& remaining, const std::vector<FittedPlane>& planes,
                           const std::unordered_set<std::int64_t>& floor_seen, const SegmentationParams& p) {
  FurnitureSegment s;
  s.points_m.reserve(c.indices.size());
  for (int i : c.indices) s.points_m.push_back(remaining[static_cast<std::size_t>(i)].getVector3fMap());
  s.centroid_m = c.centroid;
  s.footprint = FootprintOf(s.points_m);
  for (const FittedPlane& plane : planes) {
    if (plane.role != PlaneRole::kWall && plane.role != PlaneRole::kWallWithOpening) continue;
    const Eigen::Vector2d wall_n = plane.coefficients.head<2>();
    const Footprint grown = ExtendToWall(s.footprint, wall_n / wall_n.norm(), plane.coefficients[3] / wall_n.norm(), p.wall_reach_m, 0.26);
    int cells = 0, seen = 0;
    for (double u = -0.5 * grown.extent_m.x(); u <= 0.5 * grown.extent_m.x(); u += kFloorCellM) {
      for (double v = -0.5 * grown.extent_m.y(); v <= 0.5 * grown.extent_m.y(); v += kFloorCellM) {
        const Eigen::Vector2d q = grown.centre_m + Eigen::Rotation2Dd(grown.yaw_rad) * Eigen::Vector2d(u, v);
        if (Inside(s.footprint, q)) continue;
        ++cells;
        seen += floor_seen.count(FloorCellKey(q.x(), q.y())) > 0;
      }
    }
    if (cells > 0 && seen * 5 <= cells) s.footprint = grown;
  }
  s.touches_floor = c.floor;
  s.touches_wall = c.wall;
  s.merged_flying = c.merged;
  return s;
}

}  // namespace

const char* PlaneRoleName(PlaneRole role) {
  switch (role) {
    case PlaneRole::kFloor: return "floor";
    case PlaneRole::kCeiling: return "ceiling";
    case PlaneRole::kWall: return "wall";
    case PlaneRole::kWallWithOpening: return "wall_with_opening";
    case PlaneRole::kSurface: return "surface";
  }
  return "surface";
}

SegmentationResult SegmentFurniture(const std::vector<Eigen::Vector3f>& cloud_m, const SegmentationParams& p) {
  CheckParams(p);
  SegmentationResult out;
  const Cloud::Ptr thin = Thinned(cloud_m, p.voxel_m, out);
  if (thin->empty()) return out;
  const std::vector<int> plane_of = FitPlanes(thin, p, out);
  const std::unordered_set<std::int64_t> floor_seen = FloorSeen(*thin, plane_of, out.planes);
  const Cloud::Ptr remaining = WithoutBoundingPlanes(*thin, out.planes, p);
  out.remaining_points = remaining->size();
  if (remaining->empty()) return out;
  std::vector<Cluster> clusters = ClusterPieces(remaining, p, out);
  MergeFlying(*remaining, p.cluster_tolerance_m, clusters, out);
  if (p.part_overlap > 0.0) JoinParts(*remaining, p.part_overlap, clusters);
  for (const Cluster& c : clusters) {
    if (c.alive) out.segments.push_back(ToSegment(c, *remaining, out.planes, floor_seen, p));
  }
  std::sort(out.segments.begin(), out.segments.end(),
            [](const FurnitureSegment& a, const FurnitureSegment& b) { return a.points_m.size() > b.points_m.size(); });
  return out;
}

}  // namespace anchordb::engine::segmentation
