#pragma once
// Segmentation of furniture from a room cloud (thesis 5.3.1, SPEC §4.7). The cloud (map frame M, z up, metres) is
// thinned on a voxel grid; plane models are fitted one after another with RANSAC (PCL); a horizontal plane with
// (next to) nothing below it is the floor, one with nothing above it the ceiling, a vertical plane with nothing
// behind it a wall, and a vertical plane that is large enough is a wall even with points behind it (a wall with an
// open door or a passage). Those bounding planes are removed (with a thin band around them, where the sensor's noise
// spreads them); every other plane (a table top, a shelf board) stays. The rest is grouped by Euclidean clustering;
// clusters of at least `min_cluster_points` that touch the floor or a wall are furniture; "flying" clusters (touching
// neither, split off by occlusion) are merged into the nearest cluster below them, and dropped when there is none.
// Before that, a cluster whose dense ("core") points fall apart into several pieces is cut there: two pieces joined
// only by a thin trail of flying pixels at a depth discontinuity become two clusters.
// PCL stays in furniture_segmentation.cc.
#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <vector>

#include "engine/segmentation/footprint.h"

namespace anchordb::engine::segmentation {

struct SegmentationParams {
  double voxel_m = 0.02;               // voxel grid leaf [m] (PCL VoxelGrid), > 0
  double plane_distance_m = 0.03;      // RANSAC inlier distance [m]
  int plane_iterations = 300;          // RANSAC iterations per plane
  int max_planes = 16;                 // planes fitted at most
  std::size_t min_plane_points = 400;  // a plane with fewer inliers ends the plane search
  double axis_tolerance_rad = 0.15;    // a plane is horizontal / vertical within this of the ideal normal
  double behind_margin_m = 0.10;       // a point beyond the plane by more than this is "behind" it
  double max_behind_fraction = 0.003;  // of the cloud's points: up to this many behind still count as "nothing"
  // A vertical plane whose inliers span at least this width and height is a wall even with points behind it.
  double wall_min_width_m = 2.0;
  double wall_min_height_m = 1.5;
  // Around a bounding plane, points closer than this are removed too [m]: the sensor noise, and a wall seen twice
  // from poses a few centimetres apart (a merge corrects most of a pose error, not all of it).
  double band_m = 0.08;
  double outlier_radius_m = 0.05;      // a point with fewer than `outlier_min_neighbours` within this is noise
  int outlier_min_neighbours = 4;
  double cluster_tolerance_m = 0.05;   // Euclidean clustering distance [m]
  // Bridges of flying (mixed) pixels between two pieces: a point with fewer neighbours within `core_radius_m` than
  // `core_density` times its cluster's median count is not core; when the core points of a cluster fall into two or
  // more clusters of at least `min_cluster_points`, the cluster is split there and every other point joins the
  // nearest core. core_density = 0 never splits.
  double core_radius_m = 0.05;
  double core_density = 0.5;
  std::size_t min_cluster_points = 150;  // smaller clusters are not furniture (at the default voxel: ~0.06 m^2)
  double contact_m = 0.10;             // a cluster within this of the floor or a wall touches it [m]
  // A piece whose footprint ends at most this far in front of a wall extends back to it when the floor between was
  // not seen (its back and top hidden from the camera; engine/segmentation/footprint.h ExtendToWall) [m]; 0 = never.
  double wall_reach_m = 0.8;
  // A cluster whose footprint lies at least this much (share of its area) inside a larger cluster's is a part of
  // that piece split off by occlusion and joins it; 0 = never.
  double part_overlap = 0.5;
};

enum class PlaneRole { kFloor, kCeiling, kWall, kWallWithOpening, kSurface };
const char* PlaneRoleName(PlaneRole role);  // "floor", "ceiling", "wall", "wall_with_opening", "surface"

struct FittedPlane {
  PlaneRole role = PlaneRole::kSurface;
  Eigen::Vector4d coefficients = Eigen::Vector4d::Zero();  // n.x, n.y, n.z, d with |n| = 1; n points into the room
  std::size_t inliers = 0;
  std::size_t behind = 0;  // points beyond it by more than behind_margin_m
};

struct FurnitureSegment {
  std::vector<Eigen::Vector3f> points_m;  // voxel-thinned points of the segment in M
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  Footprint footprint;
  bool touches_floor = false, touches_wall = false;
  int merged_flying = 0;  // flying clusters and parts merged into it
};

struct SegmentationResult {
  std::vector<FittedPlane> planes;         // in the order RANSAC found them
  std::vector<FurnitureSegment> segments;  // largest first
  std::size_t input_points = 0;            // finite input points
  std::size_t thinned_points = 0;          // after the voxel grid
  std::size_t remaining_points = 0;        // after bounding planes and outliers
  int small_clusters = 0;                  // dropped: below min_cluster_points
  int bridges_cut = 0;                     // clusters split at a bridge of sparse points (into 2 or more)
  int flying_dropped = 0;                  // flying clusters with nothing below them
  std::optional<double> floor_z_m;         // height of the floor plane when one was found
};

// Segments `cloud_m` (non-finite points are skipped). Throws Error(kInvalidArgument) naming "params.<name>" for a
// parameter out of range. An empty cloud gives an empty result.
SegmentationResult SegmentFurniture(const std::vector<Eigen::Vector3f>& cloud_m, const SegmentationParams& params = {});

}  // namespace anchordb::engine::segmentation
