#include "sim/apartment_furnished.h"

#include "sim/apartment_parts.h"

namespace anchordb::sim {

using namespace apartment_detail;  // NOLINT: the builder and room of the settings

namespace {

// A box rotated by yaw about the footprint centre `c`, given by its offset in the piece's own axes.
void PieceBox(Builder& b, int id, const Eigen::Vector2d& c, double yaw, const Eigen::Vector3d& offset, const Eigen::Vector3d& size) {
  const Eigen::Vector2d o = Eigen::Rotation2Dd(yaw) * offset.head<2>();
  b.Box(id, Eigen::Vector3d(c.x() + o.x(), c.y() + o.y(), offset.z()), size, yaw);
}

}  // namespace

FurnishedRoom MakeFurnishedRoom(std::uint64_t seed) {
  Jitter j(seed * 2654435761u + 11);
  Builder b;
  AddRoom(b, true, 0.9, 1.8, 2.05);
  FurnishedRoom room;
  const auto yaw_jitter = [&] { return j.Uniform(-4.0, 4.0) * kDeg; };
  const auto add = [&](int id, const std::string& name, const std::string& category, const Eigen::Vector2d& c,
                       const Eigen::Vector2d& extent, double yaw, double height) {
    b.AddObject(id, name, "static");
    room.pieces.push_back({id, category, c, extent, yaw, height});
  };
  const double half_pi = 90.0 * kDeg;

  // Sofa against the west wall, its length along y: seat, back against the wall, two arms.
  {
    const Eigen::Vector2d c(-3.0 + 0.46, j.Uniform(-0.1, 0.1) + 0.3);
    const double yaw = half_pi + yaw_jitter();  // own x along the wall (world y), own -y towards the wall
    add(40, "sofa", "sofa", c, {2.0, 0.9}, yaw, 0.85);
    PieceBox(b, 40, c, yaw, {0.0, -0.1, 0.22}, {1.7, 0.7, 0.44});
    PieceBox(b, 40, c, yaw, {0.0, 0.34, 0.45}, {2.0, 0.2, 0.8});  // the back (own +y: the west wall)
    for (double s : {-1.0, 1.0}) PieceBox(b, 40, c, yaw, {s * 0.9, -0.1, 0.3}, {0.2, 0.7, 0.6});
  }
  // Dining table in the room, with a chair at its south side.
  {
    const Eigen::Vector2d c(j.Uniform(-0.1, 0.1) + 0.4, j.Uniform(-0.1, 0.1) - 0.1);
    const double yaw = yaw_jitter();
    add(41, "dining table", "table", c, {1.4, 0.8}, yaw, 0.75);
    PieceBox(b, 41, c, yaw, {0.0, 0.0, 0.73}, {1.4, 0.8, 0.04});
    for (double sx : {-1.0, 1.0}) {
      for (double sy : {-1.0, 1.0}) PieceBox(b, 41, c, yaw, {sx * 0.63, sy * 0.33, 0.355}, {0.05, 0.05, 0.71});
    }
    room.table_index = static_cast<int>(room.pieces.size()) - 1;
    room.table_top_m = Eigen::Vector3d(c.x(), c.y(), 0.75);
    const Eigen::Vector2d chair = c + Eigen::Rotation2Dd(yaw) * Eigen::Vector2d(0.2, -0.85);
    add(42, "chair", "chair", chair, {0.42, 0.46}, yaw, 0.92);
    AddChair(b, 42, chair, Eigen::Rotation2Dd(yaw) * Eigen::Vector2d(0.0, -1.0));
  }
  // Shelf against the north wall: sides, back, four boards.
  {
    const Eigen::Vector2d c(j.Uniform(-0.1, 0.1) + 1.3, 2.5 - 0.19);
    const double yaw = yaw_jitter() * 0.5;
    add(43, "shelf", "shelf", c, {1.0, 0.36}, yaw, 1.8);
    for (double s : {-1.0, 1.0}) PieceBox(b, 43, c, yaw, {s * 0.48, 0.0, 0.9}, {0.04, 0.36, 1.8});
    PieceBox(b, 43, c, yaw, {0.0, 0.165, 0.9}, {0.92, 0.03, 1.8});
    for (double z : {0.05, 0.45, 0.85, 1.25, 1.78}) PieceBox(b, 43, c, yaw, {0.0, 0.0, z}, {0.92, 0.34, 0.03});
  }
  // Wardrobe against the east wall, south of the door.
  {
    const Eigen::Vector2d c(3.0 - 0.31, j.Uniform(-0.1, 0.1) - 1.2);
    const double yaw = half_pi + yaw_jitter() * 0.5;
    add(44, "wardrobe", "wardrobe", c, {1.2, 0.6}, yaw, 2.0);
    PieceBox(b, 44, c, yaw, {0.0, 0.0, 1.0}, {1.2, 0.6, 2.0});
  }
  // Cupboard against the south wall.
  {
    const Eigen::Vector2d c(j.Uniform(-0.1, 0.1) - 1.2, -2.5 + 0.24);
    const double yaw = yaw_jitter() * 0.5;
    add(45, "cupboard", "cupboard", c, {1.2, 0.46}, yaw, 0.85);
    PieceBox(b, 45, c, yaw, {0.0, 0.0, 0.06}, {1.14, 0.40, 0.12});  // plinth
    PieceBox(b, 45, c, yaw, {0.0, 0.0, 0.49}, {1.2, 0.46, 0.74});
  }
  room.scene = b.scene();

  // Views: a robot walking through the room, each view aimed at one or two pieces.
  const auto view = [&](const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
    const Eigen::Vector3d e = eye + Eigen::Vector3d(j.Uniform(-0.05, 0.05), j.Uniform(-0.05, 0.05), j.Uniform(-0.05, 0.05));
    room.X_WorldCamera.push_back(LookAt(e, target));
  };
  const PlacedPiece& sofa = room.pieces[0];
  const PlacedPiece& table = room.pieces[1];
  const PlacedPiece& shelf = room.pieces[3];
  const PlacedPiece& wardrobe = room.pieces[4];
  const PlacedPiece& cupboard = room.pieces[5];
  const auto at = [](const PlacedPiece& p, double z) { return Eigen::Vector3d(p.centre_m.x(), p.centre_m.y(), z); };
  view(Eigen::Vector3d(-0.3, 0.5, 1.4), at(sofa, 0.4));
  view(Eigen::Vector3d(-1.0, 1.0, 1.35), at(table, 0.5));
  view(Eigen::Vector3d(1.2, 0.2, 1.45), at(shelf, 0.8));
  view(Eigen::Vector3d(0.8, 0.5, 1.4), at(wardrobe, 0.9));
  view(Eigen::Vector3d(-0.8, -0.2, 1.3), at(cupboard, 0.4));
  view(Eigen::Vector3d(2.0, 1.0, 1.4), at(table, 0.4));
  return room;
}

}  // namespace anchordb::sim
