#include "sim/sweep_scenes.h"

#include <utility>

#include "sim/apartment.h"
#include "sim/apartment_parts.h"

namespace anchordb::sim {
namespace {

using namespace apartment_detail;  // NOLINT: the room, the builder and the viewpoints of the settings

constexpr int kAddedId = 40;

// The third viewpoint: B's construction with the heading turned the other way.
Eigen::Isometry3d ThirdViewpoint(const Vector3d& look_m, double view_yaw_rad, double distance_m, double height_m) {
  return MakeViewpoints(look_m, view_yaw_rad, distance_m, height_m, 30.0 * kDeg).B;
}

// A box of about 12 x 16 x 20 cm standing on the table top whose centre is `surface_m`.
void AddAddedBox(Builder& b, Jitter& jitter, const Vector3d& surface_m, const Eigen::Vector2d& offset) {
  const Vector3d size(0.12 * jitter.Uniform(0.9, 1.1), 0.16 * jitter.Uniform(0.9, 1.1), 0.20 * jitter.Uniform(0.9, 1.1));
  const Vector3d centre(surface_m.x() + offset.x() + jitter.Uniform(-0.05, 0.05),
                        surface_m.y() + offset.y() + jitter.Uniform(-0.05, 0.05), surface_m.z() + 0.5 * size.z());
  b.AddObject(kAddedId, "added_box", "movable");
  b.Box(kAddedId, centre, size, jitter.Uniform(-20.0, 20.0) * kDeg);
}

// The tabletop setting's room and table only, and one static box on the table.
SweepScene Sparse(std::uint64_t seed) {
  const SettingScene setting = MakeSetting(Setting::kTA, seed);
  Jitter jitter(seed * 0x9E3779B97F4A7C15ULL + 77);
  Builder b;
  const auto kept = [](int id) { return id <= kWallEastId || id == kFurnitureId; };
  for (const Object& o : setting.scene.objects) if (kept(o.id)) b.scene().objects.push_back(o);
  for (const Primitive& p : setting.scene.primitives) if (kept(p.object_id)) b.scene().primitives.push_back(p);
  const Vector3d& surface = setting.surface_point_m;
  b.AddObject(kBoxId, "box", "static");
  b.Box(kBoxId, Vector3d(surface.x() + 0.15, surface.y() + 0.35, surface.z() + 0.09), Vector3d(0.25, 0.2, 0.18), 0.2);
  SweepScene out;
  out.before = b.scene();
  AddAddedBox(b, jitter, surface, {-0.05, -0.15});
  out.after = std::move(b.scene());
  out.added_id = kAddedId;
  out.X_WorldCameraA = setting.X_WorldCameraA;
  out.X_WorldCameraB = setting.X_WorldCameraB;
  out.X_WorldCameraC = ThirdViewpoint(surface, 15.0 * kDeg, 1.3, 1.3);
  return out;
}

SweepScene Cluttered(std::uint64_t seed) {
  const SettingScene setting = MakeSetting(Setting::kTA, seed);
  Jitter jitter(seed * 0x9E3779B97F4A7C15ULL + 91);
  Builder b;
  b.scene() = setting.scene;
  SweepScene out;
  out.before = b.scene();
  AddAddedBox(b, jitter, setting.surface_point_m, {-0.02, 0.12});
  out.after = std::move(b.scene());
  out.added_id = kAddedId;
  out.X_WorldCameraA = setting.X_WorldCameraA;
  out.X_WorldCameraB = setting.X_WorldCameraB;
  out.X_WorldCameraC = ThirdViewpoint(setting.surface_point_m, 15.0 * kDeg, 1.3, 1.3);
  return out;
}

}  // namespace

SweepScene MakeSweepScene(SweepSceneKind kind, std::uint64_t seed) {
  return kind == SweepSceneKind::kSparse ? Sparse(seed) : Cluttered(seed);
}

const char* SweepSceneName(SweepSceneKind kind) { return kind == SweepSceneKind::kSparse ? "sparse" : "cluttered"; }

}  // namespace anchordb::sim
