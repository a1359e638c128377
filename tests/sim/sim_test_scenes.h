#pragma once
// Small scenes, cameras and sensors shared by the renderer's tests.
#include <cstdint>
#include <initializer_list>
#include <string>

#include "sim/apartment.h"
#include "sim/renderer.h"

namespace anchordb::sim {

inline constexpr std::uint64_t kSeed = 42;

inline PinholeIntrinsics Kinect() { return KinectIntrinsics(); }

inline SensorModel Noiseless() {
  SensorModel sensor;
  sensor.noise = false;
  return sensor;
}

inline Primitive MakeBox(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, double yaw_rad = 0.0) {
  Primitive p;
  p.object_id = id;
  p.shape = Shape::kBox;
  p.X_WorldPrim.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.X_WorldPrim.translation() = centre;
  p.size_m = size;
  return p;
}

inline Primitive MakeCylinder(int id, const Eigen::Vector3d& centre, double radius, double height) {
  Primitive p;
  p.object_id = id;
  p.shape = Shape::kCylinder;
  p.X_WorldPrim.translation() = centre;
  p.size_m = Eigen::Vector3d(radius, radius, height);
  return p;
}

inline Scene SceneOf(std::initializer_list<Primitive> primitives) {
  Scene scene;
  for (const Primitive& p : primitives) {
    scene.primitives.push_back(p);
    bool known = false;
    for (const Object& o : scene.objects) known = known || o.id == p.object_id;
    if (!known) scene.objects.push_back(Object{p.object_id, "object" + std::to_string(p.object_id), "static"});
  }
  return scene;
}

// Camera 1 m above the floor at the origin, looking along world +x: optical x = world -y, optical y = world -z.
inline Eigen::Isometry3d CameraLookingAlongX(double height_m = 1.0) {
  return LookAt(Eigen::Vector3d(0.0, 0.0, height_m), Eigen::Vector3d(1.0, 0.0, height_m));
}

inline std::size_t Index(const Frame& f, int u, int v) { return static_cast<std::size_t>(v) * f.width + u; }

}  // namespace anchordb::sim
