#pragma once
// Deterministic synthetic depth renderer: scenes of boxes and cylinders seen by a pinhole structured-light depth
// camera (Kinect-like), with exact per-pixel object ids as ground truth. Every evaluation, test, benchmark and
// demo of anchordb renders its images here.
//
// Frames: the world frame W is the map frame (REP-103, z up). A camera pose X_WorldCamera is the pose of the
// camera OPTICAL frame C in W (z forward, x right, y down). Units: metres, radians; depth images in millimetres.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "schema/types.h"

namespace anchordb::sim {

enum class Shape { kBox, kCylinder };

// One solid primitive of an object.
struct Primitive {
  int object_id = 0;  // >= 1; several primitives may share one object id (a table = top + legs)
  Shape shape = Shape::kBox;
  // Pose of the primitive's centre P in the world frame W.
  Eigen::Isometry3d X_WorldPrim = Eigen::Isometry3d::Identity();
  // [m] box: full extents along its local x, y, z. Cylinder: size_m.x() = radius, size_m.z() = height, the axis
  // is the local z axis (size_m.y() is ignored by the renderer; SceneToJson writes it back as given).
  Eigen::Vector3d size_m = Eigen::Vector3d::Ones();
};

struct Object {
  int id = 0;
  std::string name;
  std::string kind;  // "static" (walls, floor, furniture) | "movable" | "person"
};

struct Scene {
  std::vector<Primitive> primitives;
  std::vector<Object> objects;
};

// The depth sensor: what it measures and where it drops measurements.
struct SensorModel {
  // Axial Gaussian noise sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 [m] (Nguyen, Izadi, Lovell 2012), added to z
  // before quantisation to mm.
  bool noise = true;
  double min_range_m = 0.5;  // no depth where the noiseless z is outside [min_range_m, max_range_m]
  double max_range_m = 5.0;
  // [rad] angle between the reversed viewing ray and the surface normal beyond which there is no depth (75 deg).
  double max_incidence_rad = 1.309;
  // [m] the projector sits at (+baseline, 0, 0) of the optical frame; a hit point it cannot see (something lies
  // more than 1 cm before it on the projector ray) gets no depth.
  double projector_baseline_m = 0.075;
  bool shadow = true;
};

// One rendered image, row-major, index = v * width + u.
struct Frame {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> depth_mm;  // measured depth [mm], 0 = no measurement (ROS 16UC1)
  std::vector<std::int32_t> object_id;  // ground truth: id of the object hit, 0 = nothing; set even where depth
                                        // was dropped (range, grazing, shadow)
  std::vector<float> true_depth_m;      // noiseless optical-frame z of the hit [m], 0 if nothing hit
};

// Ray-casts `scene` from the camera at X_WorldCamera (optical frame) with intrinsics K. Pixel (u, v) looks along
// ((u - cx) / fx, (v - cy) / fy, 1) in the optical frame; the nearest hit wins; depth is the optical z of the hit
// (not the ray length). Noise comes from std::mt19937_64 seeded with `seed`: one draw per pixel whatever the
// scene, so the same seed gives the same noise at every pixel. Deterministic: same inputs, same frame.
// Throws std::invalid_argument for non-positive image size or focal lengths, or a primitive with object_id < 1 or
// a non-positive size.
Frame Render(const Scene& scene, const PinholeIntrinsics& K, const Eigen::Isometry3d& X_WorldCamera,
             const SensorModel& sensor, std::uint64_t seed);

// The optical-frame pose of a camera at `eye` looking at `target` (world z up): image x stays horizontal, image y
// points downwards. Throws std::invalid_argument if eye == target. Looking straight up or down, image y is
// chosen along world +x.
Eigen::Isometry3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// Parses {"objects":[{"id":1,"name":"table","kind":"static","primitives":[{"shape":"box"|"cylinder",
// "position":[x,y,z], "orientation":[qx,qy,qz,qw] (optional, ROS order, within 1e-3 of unit norm, normalised),
// "size":[sx,sy,sz]}, ...]}, ...]}. Strict: unknown keys, missing fields, wrong types, non-finite or non-positive
// sizes, ids < 1, duplicate ids and unknown kinds or shapes throw std::invalid_argument naming the field.
Scene SceneFromJson(const nlohmann::json& j);
// The inverse of SceneFromJson; primitives are grouped under their object (objects in `scene.objects` order).
// Throws std::invalid_argument if a primitive's object_id has no entry in `scene.objects`.
nlohmann::json SceneToJson(const Scene& scene);

// Left-multiplies the poses of all primitives of `object_id` by X_delta_world (a motion expressed in the world
// frame: X_WorldPrim <- X_delta_world * X_WorldPrim). Throws std::invalid_argument for an unknown object id.
void MoveObject(Scene& scene, int object_id, const Eigen::Isometry3d& X_delta_world);
// Removes the object and its primitives. Throws std::invalid_argument for an unknown object id.
void RemoveObject(Scene& scene, int object_id);

}  // namespace anchordb::sim
