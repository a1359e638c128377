// The parts of the evaluation settings: the room, the small objects on a surface, furniture pieces, and the
// viewpoints A and B.
#include <cmath>
#include <limits>

#include "sim/apartment_parts.h"

namespace anchordb::sim::apartment_detail {
namespace {

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

Eigen::Isometry3d CameraFromHeading(const Vector3d& eye, double heading_rad, const Vector3d& look_m) {
  const double horizontal = std::hypot(look_m.x() - eye.x(), look_m.y() - eye.y());
  const double pitch = std::atan2(eye.z() - look_m.z(), horizontal);
  const Vector3d forward(std::cos(heading_rad) * std::cos(pitch), std::sin(heading_rad) * std::cos(pitch),
                         -std::sin(pitch));
  return LookAt(eye, eye + forward);
}

}  // namespace

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

Viewpoints MakeViewpoints(const Vector3d& look_m, double view_yaw_rad, double distance_m, double height_m,
                          double turn_rad, double a_offset_abs_rad) {
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

}  // namespace anchordb::sim::apartment_detail
