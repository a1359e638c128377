#pragma once
// Virtual scans of triangle meshes (thesis 4.1.1: "virtual 3D scans ... from 12 virtual positions around the target
// object"): a Wavefront OBJ reader (v / f lines; polygons are fanned into triangles) and a pinhole ray caster of
// our own giving the ideal depth image of a mesh from a viewpoint, and the cloud of its pixels. Sensor noise is not
// added here: callers that want it pass the ideal depth through the sim's sensor model (sim/) or their own.
// Mesh frame = model frame of the file, metres, z up.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace anchordb::engine {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<Eigen::Vector3i> triangles;  // indices into vertices_m
};

// Parses OBJ text. Throws Error(kUnprocessable, "mesh") naming the line for a face with an index out of range or
// fewer than 3 vertices, a non-finite vertex, or a file without any face; unknown statements are ignored.
TriangleMesh ParseObj(std::string_view text);

struct ScanCamera {
  int width = 320, height = 240;  // a Kinect v1 depth image at half resolution
  double fx = 285, fy = 285, cx = 159.5, cy = 119.5;  // [px]
  double max_range_m = 8.0;
};

// Ideal optical-frame depth [m] (0 = nothing hit) of `mesh`, placed in the world by X_WorldMesh, seen from the
// camera optical frame X_WorldCamera (z forward, x right, y down). Row-major, index = v * width + u.
std::vector<double> RenderMeshDepth(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WorldMesh,
                                    const ScanCamera& camera, const Eigen::Isometry3d& X_WorldCamera);
// Back-projects a depth image [m] to points in the world frame (0 skipped).
std::vector<Eigen::Vector3f> DepthToWorldPoints(const std::vector<double>& depth_m, const ScanCamera& camera,
                                                const Eigen::Isometry3d& X_WorldCamera);

// The camera poses of `views` viewpoints evenly spaced in azimuth on a circle around the mesh's bounding-box
// centre (radius: `distance_factor` x the box diagonal, at least 1 m; height: `elevation_rad` above the centre),
// each looking at the centre; the first view at azimuth `azimuth0_rad`.
std::vector<Eigen::Isometry3d> ScanViewpoints(const TriangleMesh& mesh, int views, double azimuth0_rad,
                                              double elevation_rad, double distance_factor = 1.5);

// The virtual scans of `mesh` (identity pose) from ScanViewpoints(views, 0, 0.5 rad): one cloud per view in the
// mesh frame, ideal depth (no noise). Views that see nothing give an empty cloud.
std::vector<std::vector<Eigen::Vector3f>> VirtualScans(const TriangleMesh& mesh, int views, const ScanCamera& camera);

}  // namespace anchordb::engine
