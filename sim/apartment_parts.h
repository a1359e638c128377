#pragma once
// Internal to sim/apartment*.cc: the parts the evaluation settings are built from (object ids, the room, a scene
// builder, seeded jitter, the small objects, furniture pieces, and the viewpoints A and B of a setting).
#include <Eigen/Geometry>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include "sim/apartment.h"

namespace anchordb::sim::apartment_detail {

using Eigen::Vector3d;

constexpr double kDeg = std::numbers::pi / 180.0;

// Object ids, the same in every setting.
constexpr int kFloorId = 1;
constexpr int kWallWestId = 2;
constexpr int kWallNorthId = 3;
constexpr int kWallSouthId = 4;
constexpr int kWallEastId = 5;
constexpr int kFurnitureId = 10;       // the supporting furniture (table, shelf, sideboard, counter, ...)
constexpr int kFurniture2Id = 11;      // a second piece (small table, wall cabinets, coffee table)
constexpr int kCharacteristicId = 15;  // door leaf, kitchen chair, drawer, person
constexpr int kCupId = 20;
constexpr int kBoxId = 21;
constexpr int kBookId = 22;
constexpr int kThinId = 23;
constexpr int kTallId = 24;
constexpr int kDistractorId = 30;  // 30, 31, ...

// Room: inner faces of the walls at x = +-3 m, y = +-2.5 m; walls 0.1 m thick, 2.6 m high; floor top at z = 0.
constexpr double kRoomHalfX = 3.0;
constexpr double kRoomHalfY = 2.5;
constexpr double kWallThickness = 0.1;
constexpr double kWallHeight = 2.6;

class Builder {
 public:
  void AddObject(int id, std::string name, std::string kind) {
    scene_.objects.push_back(Object{id, std::move(name), std::move(kind)});
  }
  // A box given by its centre, full extents and heading (rotation about world z) [rad].
  void Box(int id, const Vector3d& centre_m, const Vector3d& size_m, double yaw_rad = 0.0) {
    Primitive p;
    p.object_id = id;
    p.shape = Shape::kBox;
    p.X_WorldPrim.linear() = Eigen::AngleAxisd(yaw_rad, Vector3d::UnitZ()).toRotationMatrix();
    p.X_WorldPrim.translation() = centre_m;
    p.size_m = size_m;
    scene_.primitives.push_back(p);
  }
  // An axis-aligned box from its minimum and maximum corners.
  void BoxMinMax(int id, const Vector3d& min_m, const Vector3d& max_m) {
    Box(id, 0.5 * (min_m + max_m), max_m - min_m);
  }
  // A cylinder; its axis is world z unless `R_WorldPrim` turns it.
  void Cylinder(int id, const Vector3d& centre_m, double radius_m, double height_m,
                const Eigen::Matrix3d& R_WorldPrim = Eigen::Matrix3d::Identity()) {
    Primitive p;
    p.object_id = id;
    p.shape = Shape::kCylinder;
    p.X_WorldPrim.linear() = R_WorldPrim;
    p.X_WorldPrim.translation() = centre_m;
    p.size_m = Vector3d(radius_m, radius_m, height_m);
    scene_.primitives.push_back(p);
  }
  Scene& scene() { return scene_; }

 private:
  Scene scene_;
};

// Deterministic, portable random numbers (std distributions differ between standard libraries).
class Jitter {
 public:
  explicit Jitter(std::uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) {
    const double unit = static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * unit;
  }

 private:
  std::mt19937_64 rng_;
};

// Layout of the five small objects on a surface: offsets (along world x, along world y) [m] from the surface
// point of the cup, the box, the book, the thin object and the tall object.
struct Layout {
  Eigen::Vector2d cup, box, book, thin, tall;
};

// Viewpoints. A stands `distance_m` (horizontally) from `look_m`, seen along `view_yaw_rad`, at `height_m`, and
// looks down at `look_m`'s height with its heading turned by `a_offset_abs_rad` against the later turn to B (so
// that the place lies off the centre by about as much in A as in B and inside both images). B: the eye 0.45 m away,
// heading turned by `turn_rad`, the eye placed where `look_m` comes closest to B's image centre.
struct Viewpoints {
  Eigen::Isometry3d A, B;
};

// The room (floor and four walls); the east wall has a door opening when `door_in_east_wall`.
void AddRoom(Builder& b, bool door_in_east_wall, double door_y_min, double door_y_max, double door_height);
// Puts the small objects on the horizontal surface whose top centre is `surface_m`.
void AddSmallObjects(Builder& b, Jitter& jitter, const Vector3d& surface_m, const Layout& layout);
// A four-legged table (or chair seat) top with its top surface at `top_z`.
void AddLeggedTop(Builder& b, int id, const Eigen::Vector2d& centre_xy, const Vector3d& top_size, double top_z,
                  double leg_width, double inset);
// A chair whose seat centre is at `centre_xy`; its back is on the side of `back_direction` (unit, horizontal).
void AddChair(Builder& b, int id, const Eigen::Vector2d& centre_xy, const Eigen::Vector2d& back_direction);
void AddPlant(Builder& b, int id, const Eigen::Vector2d& xy);
void AddPictureOnEastWall(Builder& b, int id, double y_m, double z_m);
// A kitchen counter along the east wall (worktop top at 0.9 m) with wall cabinets above.
void AddKitchen(Builder& b, bool drawer_slot, double slot_y_half, double slot_z0, double slot_z1);
Viewpoints MakeViewpoints(const Vector3d& look_m, double view_yaw_rad, double distance_m, double height_m,
                          double turn_rad, double a_offset_abs_rad = 8.5 * kDeg);

}  // namespace anchordb::sim::apartment_detail
