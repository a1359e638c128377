#pragma once
// Segments of the movable layer (thesis 3.3.4, 3.5.2; SPEC §4.4): movable pixels back-projected into the map frame
// and clustered in 3D by Euclidean clustering (PCL), which the thesis proposes over region growing on the mask
// because touching objects at different depths and split masks of one object are told apart by real distances.
// PCL stays inside segments.cc; this interface is Eigen only.
#include <Eigen/Core>
#include <vector>

namespace anchordb::engine {

struct SegmentParams {
  double cluster_tolerance_m = 0.025;  // points closer than this belong to one cluster
  int min_points = 250;                // smaller clusters are noise or merge artefacts (pixels at full resolution)
  int max_points = 400000;
  double min_extent_m = 0.03;          // the largest side of the bounding box must reach this
  int max_input_points = 60000;        // more movable points are subsampled evenly before clustering
  int sample_points = 256;             // points kept per segment (for visibility checks on later visits)
};

struct Segment {
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();  // map frame
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();       // axis-aligned bounding box in the map frame
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();
  int points = 0;                                        // points of the cluster (before subsampling is undone)
  std::vector<Eigen::Vector3f> sample_m;                 // up to SegmentParams::sample_points of its points
  Eigen::Vector3d Extent() const { return max_m - min_m; }
};

// Clusters points p_map; largest segment first. Counts refer to the input points (subsampling is scaled back).
std::vector<Segment> ClusterSegments(const std::vector<Eigen::Vector3f>& points_map, const SegmentParams& params);

}  // namespace anchordb::engine
