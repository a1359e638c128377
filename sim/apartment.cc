#include "sim/apartment.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace anchordb::sim {
namespace {

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

void AddRoom(Builder& b, bool door_in_east_wall, double door_y_min, double door_y_max, double door_height) {
  b.AddObject(kFloorId, "floor", "static");
  b.BoxMinMax(kFloorId, Vector3d(-kRoomHalfX - 0.5, -kRoomHalfY - 0.5, -0.1),
              Vector3d(kRoomHalfX + 1.5, kRoomHalfY + 0.5, 0.0));
  const double t = kWallThickness;
  const double x0 = -kRoomHalfX - t, x1 = kRoomHalfX + t, y0 = -kRoomHalfY - t, y1 = kRoomHalfY + t;
  b.AddObject(kWallWestId, "wall_west", "static");
  b.BoxMinMax(kWallWestId, Vector3d(x0, y0, 0.0), Vector3d(-kRoomHalfX, y1, kWallHeight));
  b.AddObject(kWallNorthId, "wall_north", "static");
  b.BoxMinMax(kWallNorthId, Vector3d(-kRoomHalfX, kRoomHalfY, 0.0), Vector3d(kRoomHalfX, y1, kWallHeight));
  b.AddObject(kWallSouthId, "wall_south", "static");
  b.BoxMinMax(kWallSouthId, Vector3d(-kRoomHalfX, y0, 0.0), Vector3d(kRoomHalfX, -kRoomHalfY, kWallHeight));
  b.AddObject(kWallEastId, "wall_east", "static");
  if (!door_in_east_wall) {
    b.BoxMinMax(kWallEastId, Vector3d(kRoomHalfX, y0, 0.0), Vector3d(x1, y1, kWallHeight));
    return;
  }
  b.BoxMinMax(kWallEastId, Vector3d(kRoomHalfX, y0, 0.0), Vector3d(x1, door_y_min, kWallHeight));
  b.BoxMinMax(kWallEastId, Vector3d(kRoomHalfX, door_y_max, 0.0), Vector3d(x1, y1, kWallHeight));
  b.BoxMinMax(kWallEastId, Vector3d(kRoomHalfX, door_y_min, door_height), Vector3d(x1, door_y_max, kWallHeight));
}

// Layout of the five small objects on a surface: offsets (along world x, along world y) [m] from the surface
// point of the cup, the box, the book, the thin object and the tall object.
struct Layout {
  Eigen::Vector2d cup, box, book, thin, tall;
};

// Puts the small objects on the horizontal surface whose top centre is `surface_m`.
void AddSmallObjects(Builder& b, Jitter& jitter, const Vector3d& surface_m, const Layout& layout) {
  const auto place = [&](const Eigen::Vector2d& offset, double height_m) {
    return Vector3d(surface_m.x() + offset.x() + jitter.Uniform(-0.015, 0.015),
                    surface_m.y() + offset.y() + jitter.Uniform(-0.015, 0.015), surface_m.z() + 0.5 * height_m);
  };
  const auto scale = [&] { return jitter.Uniform(0.9, 1.1); };
  const auto heading = [&] { return jitter.Uniform(-10.0, 10.0) * kDeg; };

  b.AddObject(kCupId, "cup", "movable");
  {
    const double radius = 0.04 * scale(), height = 0.10 * scale();
    b.Cylinder(kCupId, place(layout.cup, height), radius, height);
  }
  b.AddObject(kBoxId, "box", "movable");
  {
    const Vector3d size(0.10 * scale(), 0.15 * scale(), 0.20 * scale());
    const Vector3d centre = place(layout.box, size.z());
    b.Box(kBoxId, centre, size, heading());
  }
  b.AddObject(kBookId, "book", "movable");
  {
    const Vector3d size(0.17 * scale(), 0.24 * scale(), 0.03 * scale());
    const Vector3d centre = place(layout.book, size.z());
    b.Box(kBookId, centre, size, heading());
  }
  b.AddObject(kThinId, "notepad", "movable");
  {
    const Vector3d size(0.10 * scale(), 0.15 * scale(), 0.01);
    const Vector3d centre = place(layout.thin, size.z());
    b.Box(kThinId, centre, size, heading());
  }
  b.AddObject(kTallId, "bottle", "movable");
  {
    const double radius = 0.035 * scale(), height = 0.30 * scale();
    b.Cylinder(kTallId, place(layout.tall, height), radius, height);
  }
}

// A four-legged table (or chair seat) top with its top surface at `top_z`.
void AddLeggedTop(Builder& b, int id, const Eigen::Vector2d& centre_xy, const Vector3d& top_size, double top_z,
                  double leg_width, double inset) {
  b.Box(id, Vector3d(centre_xy.x(), centre_xy.y(), top_z - 0.5 * top_size.z()), top_size);
  const double leg_height = top_z - top_size.z();
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      b.Box(id,
            Vector3d(centre_xy.x() + sx * (0.5 * top_size.x() - inset),
                     centre_xy.y() + sy * (0.5 * top_size.y() - inset), 0.5 * leg_height),
            Vector3d(leg_width, leg_width, leg_height));
    }
  }
}

// A chair whose seat centre is at `centre_xy`; its back is on the side of `back_direction` (unit, horizontal).
void AddChair(Builder& b, int id, const Eigen::Vector2d& centre_xy, const Eigen::Vector2d& back_direction) {
  AddLeggedTop(b, id, centre_xy, Vector3d(0.42, 0.42, 0.04), 0.47, 0.035, 0.03);
  const Eigen::Vector2d back_xy = centre_xy + 0.19 * back_direction;
  const Vector3d back_size =
      std::abs(back_direction.x()) > 0.5 ? Vector3d(0.04, 0.42, 0.45) : Vector3d(0.42, 0.04, 0.45);
  b.Box(id, Vector3d(back_xy.x(), back_xy.y(), 0.47 + 0.225), back_size);
}

void AddPlant(Builder& b, int id, const Eigen::Vector2d& xy) {
  b.AddObject(id, "plant", "static");
  b.Cylinder(id, Vector3d(xy.x(), xy.y(), 0.15), 0.15, 0.30);
  b.Cylinder(id, Vector3d(xy.x(), xy.y(), 0.65), 0.25, 0.70);
}

void AddPictureOnEastWall(Builder& b, int id, double y_m, double z_m) {
  b.AddObject(id, "picture", "static");
  b.BoxMinMax(id, Vector3d(kRoomHalfX - 0.02, y_m - 0.3, z_m - 0.2), Vector3d(kRoomHalfX, y_m + 0.3, z_m + 0.2));
}

// Viewpoints. A stands `distance_m` (horizontally) from `look_m`, seen along `view_yaw_rad`, at `height_m`, and
// looks down at `look_m`'s height with its heading turned by `a_offset_abs_rad` against the later turn to B (so
// that the place lies off the centre by about as much in A as in B and inside both images). B: the eye 0.45 m away,
// heading turned by `turn_rad`, the eye placed where `look_m` comes closest to B's image centre.
struct Viewpoints {
  Eigen::Isometry3d A, B;
};

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

Eigen::Isometry3d CameraFromHeading(const Vector3d& eye, double heading_rad, const Vector3d& look_m) {
  const double horizontal = std::hypot(look_m.x() - eye.x(), look_m.y() - eye.y());
  const double pitch = std::atan2(eye.z() - look_m.z(), horizontal);
  const Vector3d forward(std::cos(heading_rad) * std::cos(pitch), std::sin(heading_rad) * std::cos(pitch),
                         -std::sin(pitch));
  return LookAt(eye, eye + forward);
}

Viewpoints MakeViewpoints(const Vector3d& look_m, double view_yaw_rad, double distance_m, double height_m,
                          double turn_rad, double a_offset_abs_rad = 8.5 * kDeg) {
  constexpr double kDisplacementM = 0.45;
  const double a_offset_rad = (turn_rad < 0.0 ? 1.0 : -1.0) * a_offset_abs_rad;
  const Vector3d eye_a(look_m.x() - distance_m * std::cos(view_yaw_rad),
                       look_m.y() - distance_m * std::sin(view_yaw_rad), height_m);
  const double heading_a = view_yaw_rad + a_offset_rad;
  const double heading_b = heading_a + turn_rad;
  Vector3d best_eye = eye_a;
  double best_error = std::numeric_limits<double>::infinity();
  for (int step = 0; step < 720; ++step) {
    const double gamma = step * 0.5 * kDeg;
    const Vector3d eye = eye_a + kDisplacementM * Vector3d(std::cos(gamma), std::sin(gamma), 0.0);
    const double to_look = std::atan2(look_m.y() - eye.y(), look_m.x() - eye.x());
    const double error = std::abs(WrapAngle(to_look - heading_b));
    if (error < best_error) {
      best_error = error;
      best_eye = eye;
    }
  }
  return {CameraFromHeading(eye_a, heading_a, look_m), CameraFromHeading(best_eye, heading_b, look_m)};
}

std::uint64_t SettingSeed(Setting s, std::uint64_t seed) {
  return seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(s) * 0xD1B54A32D192ED03ULL + 1;
}

SettingScene MakeTabletop(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  const Eigen::Vector2d table_xy(2.3, 0.0);
  b.AddObject(kFurnitureId, "table", "static");
  AddLeggedTop(b, kFurnitureId, table_xy, Vector3d(0.8, 1.2, 0.03), 0.75, 0.05, 0.05);
  const Vector3d surface(table_xy.x(), table_xy.y(), 0.75);
  AddSmallObjects(b, jitter, surface, {{-0.20, -0.32}, {0.10, -0.08}, {-0.14, 0.30}, {-0.22, 0.02}, {0.22, 0.36}});
  b.AddObject(kDistractorId, "chair", "static");
  AddChair(b, kDistractorId, {2.3, 0.9}, {0.0, 1.0});
  AddPlant(b, kDistractorId + 1, {2.65, -1.25});
  AddPictureOnEastWall(b, kDistractorId + 2, 0.2, 1.55);
  b.AddObject(kDistractorId + 3, "waste_bin", "static");
  b.Cylinder(kDistractorId + 3, Vector3d(1.5, -1.0, 0.175), 0.13, 0.35);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.3, 1.3, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeShelf(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "shelf", "static");
  const double x0 = 2.6, x1 = kRoomHalfX, y_half = 0.5, height = 1.8, panel = 0.02;
  b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half, 0.0), Vector3d(x1, -y_half + panel, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x0, y_half - panel, 0.0), Vector3d(x1, y_half, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x1 - panel, -y_half + panel, 0.0), Vector3d(x1, y_half - panel, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half + panel, 0.0), Vector3d(x1 - panel, y_half - panel, 0.06));
  for (const double top : {0.08, 0.42, 0.80, 1.20, 1.80}) {
    b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half + panel, top - panel), Vector3d(x1 - panel, y_half - panel, top));
  }
  const Vector3d surface(0.5 * (x0 + x1 - panel), 0.0, 0.80);
  AddSmallObjects(b, jitter, surface, {{-0.07, -0.37}, {0.05, -0.19}, {-0.05, 0.04}, {-0.08, 0.27}, {0.08, 0.41}});
  b.AddObject(kDistractorId, "row_of_books", "static");
  b.Box(kDistractorId, Vector3d(2.85, -0.15, 0.42 + 0.125), Vector3d(0.22, 0.5, 0.25));
  b.AddObject(kDistractorId + 1, "vase", "static");
  b.Cylinder(kDistractorId + 1, Vector3d(2.8, 0.2, 1.20 + 0.12), 0.06, 0.24);
  AddPlant(b, kDistractorId + 2, {2.7, 1.0});
  AddPictureOnEastWall(b, kDistractorId + 3, -1.1, 1.5);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.5, 1.3, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeArmchair(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "armchair", "static");
  const double ay = 0.6;
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay - 0.4, 0.0), Vector3d(2.9, ay + 0.4, 0.42));
  b.BoxMinMax(kFurnitureId, Vector3d(2.7, ay - 0.4, 0.42), Vector3d(2.9, ay + 0.4, 0.95));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay - 0.4, 0.42), Vector3d(2.7, ay - 0.26, 0.64));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay + 0.26, 0.42), Vector3d(2.7, ay + 0.4, 0.64));
  b.AddObject(kFurniture2Id, "small_table", "static");
  const Vector3d surface(2.45, -0.35, 0.55);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.535), 0.35, 0.03);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.265), 0.04, 0.51);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.01), 0.22, 0.02);
  AddSmallObjects(b, jitter, surface, {{-0.17, -0.10}, {0.06, -0.17}, {-0.05, 0.14}, {-0.21, 0.06}, {0.18, 0.12}});
  b.AddObject(kDistractorId, "floor_lamp", "static");
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 0.015), 0.15, 0.03);
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 0.78), 0.015, 1.5);
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 1.6), 0.2, 0.25);
  AddPlant(b, kDistractorId + 1, {2.7, 1.45});
  b.AddObject(kDistractorId + 2, "rug", "static");
  b.BoxMinMax(kDistractorId + 2, Vector3d(1.3, -1.0, 0.0), Vector3d(2.6, 1.1, 0.01));
  AddPictureOnEastWall(b, kDistractorId + 3, 0.0, 1.6);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.3, 1.2, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeDoor(Jitter& jitter) {
  Builder b;
  const double door_y0 = -1.15, door_y1 = -0.25, door_height = 2.05;
  AddRoom(b, true, door_y0, door_y1, door_height);
  b.AddObject(kDistractorId, "corridor", "static");
  b.BoxMinMax(kDistractorId, Vector3d(4.2, -kRoomHalfY - 0.1, 0.0), Vector3d(4.3, kRoomHalfY + 0.1, kWallHeight));
  b.BoxMinMax(kDistractorId, Vector3d(kRoomHalfX + 0.1, kRoomHalfY, 0.0), Vector3d(4.2, kRoomHalfY + 0.1, kWallHeight));
  b.BoxMinMax(kDistractorId, Vector3d(kRoomHalfX + 0.1, -kRoomHalfY - 0.1, 0.0),
              Vector3d(4.2, -kRoomHalfY, kWallHeight));
  // The leaf, hinged at (3.0, door_y0) on the room side, opened 30 deg into the room.
  b.AddObject(kCharacteristicId, "door", "movable");
  b.BoxMinMax(kCharacteristicId, Vector3d(kRoomHalfX, door_y0, 0.01),
              Vector3d(kRoomHalfX + 0.04, door_y1 - 0.02, door_height - 0.02));
  b.Box(kCharacteristicId, Vector3d(kRoomHalfX - 0.03, door_y1 - 0.1, 1.0), Vector3d(0.06, 0.12, 0.02));  // handle
  const Vector3d hinge(kRoomHalfX, door_y0, 0.0);
  const Eigen::Isometry3d open =
      Eigen::Translation3d(hinge) * Eigen::AngleAxisd(30.0 * kDeg, Vector3d::UnitZ()) * Eigen::Translation3d(-hinge);
  MoveObject(b.scene(), kCharacteristicId, open);

  b.AddObject(kFurnitureId, "sideboard", "static");
  b.BoxMinMax(kFurnitureId, Vector3d(2.55, 0.0, 0.0), Vector3d(kRoomHalfX, 1.0, 0.85));
  const Vector3d surface(2.775, 0.5, 0.85);
  AddSmallObjects(b, jitter, surface, {{-0.10, -0.33}, {0.05, -0.14}, {-0.05, 0.10}, {-0.12, 0.31}, {0.12, 0.38}});
  AddPlant(b, kDistractorId + 1, {2.7, 1.5});
  AddPictureOnEastWall(b, kDistractorId + 2, 0.5, 1.55);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.8, -0.05, 0.85), 0.0, 1.8, 1.4, 35.0 * kDeg, 0.0);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

// A kitchen counter along the east wall (worktop top at 0.9 m) with wall cabinets above.
void AddKitchen(Builder& b, bool drawer_slot, double slot_y_half, double slot_z0, double slot_z1) {
  b.AddObject(kFurnitureId, "kitchen_counter", "static");
  const double front = 2.42, y_half = 1.3;
  if (!drawer_slot) {
    b.BoxMinMax(kFurnitureId, Vector3d(front, -y_half, 0.0), Vector3d(kRoomHalfX, y_half, 0.86));
  } else {
    b.BoxMinMax(kFurnitureId, Vector3d(front, -y_half, 0.0), Vector3d(kRoomHalfX, y_half, slot_z0));
    b.BoxMinMax(kFurnitureId, Vector3d(front, -y_half, slot_z0), Vector3d(kRoomHalfX, -slot_y_half, 0.86));
    b.BoxMinMax(kFurnitureId, Vector3d(front, slot_y_half, slot_z0), Vector3d(kRoomHalfX, y_half, 0.86));
    b.BoxMinMax(kFurnitureId, Vector3d(kRoomHalfX - 0.05, -slot_y_half, slot_z0),
                Vector3d(kRoomHalfX, slot_y_half, slot_z1));
    b.BoxMinMax(kFurnitureId, Vector3d(front, -slot_y_half, slot_z1), Vector3d(kRoomHalfX, slot_y_half, 0.86));
  }
  b.BoxMinMax(kFurnitureId, Vector3d(front - 0.04, -y_half, 0.86), Vector3d(kRoomHalfX, y_half, 0.9));
  b.AddObject(kFurniture2Id, "wall_cabinets", "static");
  b.BoxMinMax(kFurniture2Id, Vector3d(kRoomHalfX - 0.35, -y_half, 1.5), Vector3d(kRoomHalfX, y_half, 2.2));
}

SettingScene MakeKitchenLargeObject(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  AddKitchen(b, false, 0, 0, 0);
  b.AddObject(kCharacteristicId, "kitchen_chair", "movable");
  AddChair(b, kCharacteristicId, {1.95, -0.8}, {0.0, -1.0});
  const Vector3d surface(2.69, 0.0, 0.9);
  AddSmallObjects(b, jitter, surface, {{-0.14, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.30}, {0.16, 0.33}});
  b.AddObject(kDistractorId, "kettle", "static");
  b.Cylinder(kDistractorId, Vector3d(2.75, -0.95, 0.9 + 0.11), 0.08, 0.22);
  b.AddObject(kDistractorId + 1, "toaster", "static");
  b.Box(kDistractorId + 1, Vector3d(2.8, 0.95, 0.9 + 0.1), Vector3d(0.18, 0.28, 0.2));
  b.AddObject(kDistractorId + 2, "waste_bin", "static");
  b.Cylinder(kDistractorId + 2, Vector3d(2.2, 1.6, 0.2), 0.15, 0.4);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.5, -0.2, 0.75), 5.0 * kDeg, 1.6, 1.35, 35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeKitchenDrawer(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  const double slot_y_half = 0.3, slot_z0 = 0.68, slot_z1 = 0.84;
  AddKitchen(b, true, slot_y_half, slot_z0, slot_z1);
  // The drawer, closed: its front panel stands 2 cm proud of the counter front, its body fills the slot.
  b.AddObject(kCharacteristicId, "drawer", "movable");
  const double front = 2.42, back = 2.92;
  b.BoxMinMax(kCharacteristicId, Vector3d(front - 0.02, -slot_y_half, slot_z0 + 0.005),
              Vector3d(front, slot_y_half, slot_z1 - 0.005));
  b.BoxMinMax(kCharacteristicId, Vector3d(front - 0.05, -0.1, 0.755), Vector3d(front - 0.02, 0.1, 0.775));  // handle
  b.BoxMinMax(kCharacteristicId, Vector3d(front, -slot_y_half + 0.01, slot_z0 + 0.01),
              Vector3d(back, slot_y_half - 0.01, slot_z0 + 0.02));
  b.BoxMinMax(kCharacteristicId, Vector3d(front, -slot_y_half + 0.01, slot_z0 + 0.02),
              Vector3d(back, -slot_y_half + 0.02, slot_z1 - 0.03));
  b.BoxMinMax(kCharacteristicId, Vector3d(front, slot_y_half - 0.02, slot_z0 + 0.02),
              Vector3d(back, slot_y_half - 0.01, slot_z1 - 0.03));
  b.BoxMinMax(kCharacteristicId, Vector3d(back - 0.01, -slot_y_half + 0.02, slot_z0 + 0.02),
              Vector3d(back, slot_y_half - 0.02, slot_z1 - 0.03));
  const Vector3d surface(2.69, 0.0, 0.9);
  AddSmallObjects(b, jitter, surface, {{-0.14, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.30}, {0.16, 0.33}});
  b.AddObject(kDistractorId, "kettle", "static");
  b.Cylinder(kDistractorId, Vector3d(2.75, -0.85, 0.9 + 0.11), 0.08, 0.22);
  b.AddObject(kDistractorId + 1, "fruit_bowl", "static");
  b.Cylinder(kDistractorId + 1, Vector3d(2.78, 0.8, 0.9 + 0.04), 0.12, 0.08);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.6, 0.0, 0.82), 15.0 * kDeg, 1.35, 1.35, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeSofa(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "sofa", "static");
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, -1.0, 0.0), Vector3d(kRoomHalfX, 1.0, 0.42));
  b.BoxMinMax(kFurnitureId, Vector3d(2.78, -1.0, 0.42), Vector3d(kRoomHalfX, 1.0, 0.85));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, -1.0, 0.42), Vector3d(2.78, -0.85, 0.62));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, 0.85, 0.42), Vector3d(2.78, 1.0, 0.62));
  // A person lying on the sofa along y, head at +y.
  b.AddObject(kCharacteristicId, "person", "person");
  const Eigen::Matrix3d axis_along_y = Eigen::AngleAxisd(-0.5 * std::numbers::pi, Vector3d::UnitX()).toRotationMatrix();
  const double px = 2.45, seat = 0.42;
  b.Box(kCharacteristicId, Vector3d(px, 0.32, seat + 0.11), Vector3d(0.36, 0.60, 0.22));
  b.Cylinder(kCharacteristicId, Vector3d(px, 0.73, seat + 0.10), 0.10, 0.22, axis_along_y);
  b.Cylinder(kCharacteristicId, Vector3d(px - 0.09, -0.405, seat + 0.075), 0.075, 0.85, axis_along_y);
  b.Cylinder(kCharacteristicId, Vector3d(px + 0.09, -0.405, seat + 0.075), 0.075, 0.85, axis_along_y);
  b.AddObject(kFurniture2Id, "coffee_table", "static");
  AddLeggedTop(b, kFurniture2Id, {1.55, 0.0}, Vector3d(0.6, 1.0, 0.03), 0.45, 0.04, 0.04);
  const Vector3d surface(1.55, 0.0, 0.45);
  AddSmallObjects(b, jitter, surface, {{-0.15, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.32}, {0.17, 0.35}});
  AddPlant(b, kDistractorId, {2.7, 1.5});
  AddPictureOnEastWall(b, kDistractorId + 1, 0.0, 1.5);
  b.AddObject(kDistractorId + 2, "floor_lamp", "static");
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 0.015), 0.15, 0.03);
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 0.78), 0.015, 1.5);
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 1.6), 0.2, 0.25);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(1.9, 0.0, 0.5), 15.0 * kDeg, 1.75, 1.35, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

}  // namespace

SettingScene MakeSetting(Setting s, std::uint64_t seed) {
  Jitter jitter(SettingSeed(s, seed));
  SettingScene out;
  switch (s) {
    case Setting::kTA:
      out = MakeTabletop(jitter);
      break;
    case Setting::kSE:
      out = MakeShelf(jitter);
      break;
    case Setting::kCA:
      out = MakeArmchair(jitter);
      break;
    case Setting::kDO:
      out = MakeDoor(jitter);
      break;
    case Setting::kKI1:
      out = MakeKitchenLargeObject(jitter);
      break;
    case Setting::kKI2:
      out = MakeKitchenDrawer(jitter);
      break;
    case Setting::kSO:
      out = MakeSofa(jitter);
      break;
    default:
      throw std::invalid_argument("MakeSetting: unknown setting");
  }
  out.thin_object_id = kThinId;
  out.tall_object_id = kTallId;
  return out;
}

const char* SettingName(Setting s) {
  switch (s) {
    case Setting::kTA:
      return "TA";
    case Setting::kSE:
      return "SE";
    case Setting::kCA:
      return "CA";
    case Setting::kDO:
      return "DO";
    case Setting::kKI1:
      return "KI1";
    case Setting::kKI2:
      return "KI2";
    case Setting::kSO:
      return "SO";
  }
  return "?";
}

std::vector<Setting> AllSettings() {
  return {Setting::kTA, Setting::kSE, Setting::kCA, Setting::kDO, Setting::kKI1, Setting::kKI2, Setting::kSO};
}

PinholeIntrinsics KinectIntrinsics() {
  PinholeIntrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = 525.0;
  K.fy = 525.0;
  K.cx = 319.5;
  K.cy = 239.5;
  return K;
}

}  // namespace anchordb::sim
