#pragma once
// Server-side feature extraction from a keyframe's cloud (thesis 4.3.2, SPEC §4.6): PCL normals, FPFH and SHOT at
// keypoints of a voxel grid, and the scene plane descriptor "spd" of RANSAC planes anchored at their centroids.
// Input and anchors in the map frame [m] (z up, REP-103).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace anchordb::engine {

struct ExtractionParams {
  double voxel_m = 0.02;           // the cloud is thinned to this voxel size first
  double normal_radius_m = 0.05;   // neighbourhood of the normal estimate
  double feature_radius_m = 0.12;  // support radius of FPFH and SHOT (> normal radius)
  double keypoint_voxel_m = 0.15;  // one keypoint per voxel of this size (its centroid)
  int max_planes = 8;              // RANSAC planes extracted one after the other
  double plane_distance_m = 0.02;  // RANSAC inlier distance
  int min_plane_points = 150;      // smaller planes end the plane search (points after thinning)
};

struct ExtractedFeature {
  std::string type;  // fpfh | shot | spd
  std::vector<float> descriptor;
  Eigen::Vector3d anchor_m = Eigen::Vector3d::Zero();
};

// The spd descriptor of one plane (kSpdDims = 8 values): area [m^2] (inliers x voxel^2), |n . z| (1 horizontal),
// centroid height z [m], extents along the plane's two principal axes [m] (2 sigma each, major then minor),
// minor / major, share of the cloud's points, distance of the plane from the sensor [m].
//
// `types` is a subset of {fpfh, shot, spd}; `sensor_origin_m` orients the normals towards the sensor. Returns every
// feature of those types; an empty or tiny cloud gives none.
std::vector<ExtractedFeature> ExtractFeatures(const std::vector<Eigen::Vector3f>& points_m,
                                              const Eigen::Vector3d& sensor_origin_m,
                                              const std::vector<std::string>& types, const ExtractionParams& params);

}  // namespace anchordb::engine
