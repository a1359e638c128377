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

// The depth sensor: what it measures and where it drops measurements. The defaults model a Kinect v1 (a
// structured-light camera: an IR projector beside an IR camera, depth triangulated from the disparity of a speckle
// pattern). Every artefact has its own switch; with all of the switches added for issue 13 off
// (`quantise_disparity`, `correlated_noise_fraction` = 0, `lateral_jitter`, `flying_pixels`, `speckle_dropouts`)
// the renderer gives bit for bit the frames of the earlier, kinder sensor. Sources: sim/README.md.
struct SensorModel {
  // Master switch of every measurement error below (axial and correlated noise, quantisation, lateral jitter,
  // flying pixels, speckle dropouts): false = an exact sensor, the noiseless z rounded to mm, dropped only by
  // range, incidence and shadow (what every caller asking for exact geometry means). When true:
  // axial Gaussian noise of total sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 [m] (Nguyen, Izadi, Lovell 2012, fitted
  // to real Kinect v1 depth, which is already quantised). With `quantise_disparity` the Gaussian part is reduced
  // to sqrt(sigma^2 - step^2 / 12), so that noise and quantisation together keep Nguyen's sigma.
  bool noise = true;
  bool axial_noise = true;  // the Gaussian axial noise alone (off: the other errors stay, e.g. to isolate them)
  // Share of the noise variance that is spatially correlated (a Gaussian field on a grid of
  // `correlated_noise_spacing_px`, bilinearly upsampled and normalised to unit variance); the rest is white. The
  // Kinect matches a correlation window of about 9 x 9 px (Konolige & Mihelich), so neighbouring pixels share most
  // of their window and of their error. 0 = white noise only (the earlier sensor). Every frame draws a new field.
  double correlated_noise_fraction = 0.8;
  double correlated_noise_spacing_px = 4.0;  // [px] grid spacing of the correlated field, >= 1
  double min_range_m = 0.5;  // no depth where the noiseless z is outside [min_range_m, max_range_m]
  double max_range_m = 5.0;
  // [rad] angle between the reversed viewing ray and the surface normal beyond which there is no depth (75 deg).
  double max_incidence_rad = 1.309;
  // [m] the projector sits at (+baseline, 0, 0) of the optical frame (to the IR camera's right, as on the Kinect
  // v1, so shadows fall left of foreground objects); a hit point it cannot see (something lies more than 1 cm
  // before it on the projector ray) gets no depth. Also the triangulation baseline of `quantise_disparity`.
  double projector_baseline_m = 0.075;
  bool shadow = true;
  // Disparity quantisation (Khoshelham & Oude Elberink 2012; Konolige & Mihelich): depth is z = f b / d with the
  // disparity d measured in steps of `disparity_step_px` of the IR camera (focal length `disparity_focal_px`,
  // baseline `projector_baseline_m`), so depth comes in steps of about z^2 * step / (f b): 2.9 mm at 1 m, 26 mm at
  // 3 m, 72 mm at 5 m with the defaults. Applied after the noise, before the rounding to mm.
  bool quantise_disparity = true;
  double disparity_focal_px = 580.0;  // [px] IR camera focal length (not the depth image's K, which may differ)
  double disparity_step_px = 0.125;   // [px] 1/8 px sub-pixel steps
  // Lateral noise (Nguyen et al. 2012: sigma_L about 0.8 px): every pixel reports the measurement of a pixel
  // displaced by a spatially correlated Gaussian offset (sigma `lateral_sigma_px` per axis, same grid as the
  // correlated noise, rounded to whole pixels), so edges wobble along their length. Ground truth ids stay exact.
  bool lateral_jitter = true;
  double lateral_sigma_px = 0.8;
  // Flying (mixed) pixels at depth discontinuities: a pixel whose (2 r + 1)^2 neighbourhood, r =
  // `flying_band_px`, holds depths whose disparities differ by more than `flying_min_jump_px` is an edge pixel;
  // of the edge pixels a share `flying_fraction` reports a depth uniformly between the nearest and the farthest
  // depth of that neighbourhood, and a further share `edge_dropout_fraction` reports none.
  bool flying_pixels = true;
  int flying_band_px = 1;
  double flying_min_jump_px = 0.5;
  double flying_fraction = 0.3;
  double edge_dropout_fraction = 0.2;
  // Speckle dropouts and small holes: the pixels where a Gaussian field on a grid of `dropout_spacing_px`
  // (upsampled, unit variance) exceeds its (1 - `dropout_fraction`) quantile get no depth: spatially clustered
  // holes of a few pixels, a new pattern every frame.
  bool speckle_dropouts = true;
  double dropout_fraction = 0.01;
  double dropout_spacing_px = 3.0;  // [px] >= 1
};

// The sensor of the earlier renderer: axial white noise, range, incidence and shadow only.
SensorModel KindSensor();

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
// (not the ray length). Noise comes from std::mt19937_64 seeded with `seed` (and streams derived from it): the
// white noise is one draw per pixel whatever the scene, the correlated fields, lateral offsets, dropouts and the
// flying-pixel draws are functions of the seed and the pixel only, so the same seed gives the same noise at every
// pixel and a change of the scene changes only the pixels it reaches (within the lateral offsets and the flying
// band). Deterministic: same inputs, same frame.
// Throws std::invalid_argument for non-positive image size or focal lengths, a primitive with object_id < 1 or
// a non-positive size, or sensor parameters out of their documented ranges.
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
