#pragma once
// Synthetic rooms of the six categories of thesis 4.3 (bedroom, dining room, living room, bathroom, office,
// kitchen), box-built furniture and fixtures in randomised sizes and places, with camera poses from which a robot
// in the room's middle scans it (for the room classification evaluation; thesis 4.3.3). Map frame: z up, the room
// spans [0, size.x] x [0, size.y]; floor and four walls 2.5 m high. Seeded: the same (category, seed) gives the same
// room.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/renderer.h"

namespace anchordb::sim {

inline constexpr int kRoomCategoryCount = 6;
// "bedroom", "dining_room", "living_room", "bathroom", "office", "kitchen"
const char* RoomCategoryName(int category);

// A piece of furniture or a fixture as MakeRoom placed it (the floor and walls are none): the bounding box of its
// primitives in its own frame, x along the wall it stands against (or its length), y away from that wall (towards its
// front), z up. The mesh-furnished rooms (tests/eval/mesh_rooms.h) replace pieces by meshes at these boxes.
struct RoomPiece {
  int object_id = 0;
  std::string name;                                    // "bed", "chair", "cabinet", "kitchen counter", ...
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  // footprint centre in the world frame
  double yaw_rad = 0.0;                                // of its own x axis
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();  // along its own x and y
  double z0_m = 0.0, height_m = 0.0;                   // bottom above the floor, height
  bool against_wall = false;                           // placed with its back (own -y side) to a wall
};

struct Room {
  int category = 0;
  Scene scene;
  std::vector<RoomPiece> pieces;  // every object but the room's structure, in scene.objects order
  Eigen::Vector2d size_m = Eigen::Vector2d::Zero();
  std::vector<Eigen::Isometry3d> X_WorldCamera;  // optical-frame poses of the scanning keyframes
};

// A room of `category` in [0, 6). Some pieces occur in several categories (chairs, tables, shelves, cabinets) and
// every room gets one or two clutter boxes, so that no single piece decides the category.
Room MakeRoom(int category, std::uint64_t seed);

}  // namespace anchordb::sim
