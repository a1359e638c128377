#pragma once
// Furniture meshes (../shared/data/aws_small_house/furniture_converted) in box-built synthetic rooms, shared by the
// segmentation evaluation's mesh rooms (segmentation_eval.h) and the rooms evaluation's mesh variant (mesh_rooms.h):
// reading a mesh, fitting it to the footprint of a box-built piece, z-buffering meshes over a rendered box scene,
// and one keyframe of a box scene with meshes measured by the sim's sensor model.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "engine/shapes/virtual_scan.h"
#include "sim/renderer.h"

namespace anchordb::eval {

// The mesh of an OBJ file; nullopt when the file cannot be read (a malformed one throws as engine::ParseObj).
std::optional<engine::TriangleMesh> ReadObjFile(const std::string& path);

// The axis-aligned bounding box of a mesh in its own frame.
struct MeshBounds {
  Eigen::Vector3f lo, hi;
};
MeshBounds Bounds(const engine::TriangleMesh& mesh);

// Where a mesh stands in place of a piece.
struct MeshFit {
  Eigen::Isometry3d X_WorldMesh = Eigen::Isometry3d::Identity();
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  // its bounding box's footprint centre, world
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();  // its footprint along the piece's own x and y
  double height_m = 0.0;
};

// Puts a mesh of bounding box `b` on a piece's footprint (centre, yaw of the piece's own x, depth along its own y):
// the mesh frame turned by quarter_turns x 90 deg from the piece's axes, its box centred on the footprint and its
// bottom at z0_m. wall_side +1 / -1: the piece stands with its own +y / -y side at a wall, and the mesh's box is moved
// along the piece's y so that it ends at that wall where the piece did; 0: centred.
MeshFit FitMesh(const MeshBounds& b, int quarter_turns, const Eigen::Vector2d& centre_m, double yaw_rad,
                double piece_depth_m, double wall_side, double z0_m = 0.0);

struct PlacedMesh {
  const engine::TriangleMesh* mesh = nullptr;
  Eigen::Isometry3d X_WorldMesh = Eigen::Isometry3d::Identity();
};

// The pinhole of K as the mesh ray caster's camera.
engine::ScanCamera ScanCameraOf(const PinholeIntrinsics& K);

// Renders the meshes in order into the z-buffer `nearest` [m] (one value per pixel, <= 0: nothing there yet):
// wherever a mesh's ideal depth z > min_z_m (>= 0) lies nearer than the buffer, calls nearer(pixel, z), then stores z.
void ZBufferMeshes(const std::vector<PlacedMesh>& meshes, const engine::ScanCamera& camera,
                   const Eigen::Isometry3d& X_WorldCamera, double min_z_m, std::vector<double>& nearest,
                   const std::function<void(std::size_t, double)>& nearer);

// One keyframe of `scene` with `meshes` in it [mm, 0 = no measurement], measured by the sim's sensor model
// (sim::detail::MeasureDepth: axial and correlated noise, disparity quantisation, lateral jitter, flying pixels,
// dropouts) on the joint ideal depth: the boxes' where the renderer's exact sensor measures them (range, incidence,
// projector shadow), the meshes' where they are nearer, within range, and not grazing (incidence from the depth
// image's local normal; the sim's 75 deg). Not modelled: the projector's shadows cast by or onto meshes.
std::vector<std::uint16_t> ScanWithMeshes(const sim::Scene& scene, const std::vector<PlacedMesh>& meshes,
                                          const PinholeIntrinsics& K, const Eigen::Isometry3d& X_WorldCamera,
                                          const sim::SensorModel& sensor, std::uint64_t seed);

}  // namespace anchordb::eval
