#include "sim/rooms.h"

#include <cmath>
#include <random>

namespace anchordb::sim {
namespace {

class RoomBuilder {
 public:
  RoomBuilder(Room& room, std::uint64_t seed) : room_(room), rng_(seed) {}

  double Uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0); }
  double Vary(double v) { return v * Uniform(0.85, 1.15); }
  bool Chance(double p) { return Uniform(0, 1) < p; }

  // A box with its bottom at height `z0` [m], centred at (x, y), rotated by yaw about z.
  void Box(int object, double x, double y, double z0, double sx, double sy, double sz, double yaw) {
    Primitive p;
    p.object_id = object;
    p.shape = Shape::kBox;
    p.X_WorldPrim = Eigen::Translation3d(x, y, z0 + sz / 2) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
    p.size_m = Eigen::Vector3d(sx, sy, sz);
    room_.scene.primitives.push_back(p);
  }
  int NewObject(const std::string& name) {
    const int id = static_cast<int>(room_.scene.objects.size()) + 1;
    room_.scene.objects.push_back({id, name, "static"});
    against_wall_.push_back(false);
    return id;
  }
  // Local (u, v) of a piece placed with its back to a wall: u along the wall, v away from it.
  struct Place {
    double x, y, yaw;
    bool against_wall = false;  // its back (local -y) at a wall
    Eigen::Vector2d At(double u, double v) const {
      return {x + std::cos(yaw) * u - std::sin(yaw) * v, y + std::sin(yaw) * u + std::cos(yaw) * v};
    }
  };
  // A random place against wall `wall` (0..3) for a piece `depth` deep, or a random wall.
  Place AgainstWall(double depth, int wall = -1) {
    if (wall < 0) wall = static_cast<int>(rng_() % 4);
    const double w = room_.size_m.x(), h = room_.size_m.y();
    const double t = Uniform(0.25, 0.75);
    switch (wall) {
      case 0: return {t * w, depth / 2, 0.0, true};              // y = 0 wall, facing +y
      case 1: return {w - depth / 2, t * h, M_PI / 2, true};     // x = w wall, facing -x
      case 2: return {t * w, h - depth / 2, M_PI, true};         // y = h wall
      default: return {depth / 2, t * h, -M_PI / 2, true};       // x = 0 wall
    }
  }
  Place Middle() { return {Uniform(0.35, 0.65) * room_.size_m.x(), Uniform(0.35, 0.65) * room_.size_m.y(), Uniform(0, M_PI)}; }
  // A piece of `sx` (along the wall) x `sy` (deep) x `sz` at place p, offset (u, v).
  void Piece(int object, const Place& p, double u, double v, double z0, double sx, double sy, double sz) {
    const Eigen::Vector2d c = p.At(u, v);
    Box(object, c.x(), c.y(), z0, sx, sy, sz, p.yaw);
    if (p.against_wall) against_wall_[static_cast<std::size_t>(object - 1)] = true;
  }
  bool IsAgainstWall(int object) const { return against_wall_[static_cast<std::size_t>(object - 1)]; }

  void Table(const Place& p, double top_h, double sx, double sy) {
    const int id = NewObject("table");
    Piece(id, p, 0, 0, top_h - 0.04, sx, sy, 0.04);
    for (int i = 0; i < 4; ++i) Piece(id, p, (i % 2 ? 1 : -1) * (sx / 2 - 0.05), (i / 2 ? 1 : -1) * (sy / 2 - 0.05), 0, 0.05, 0.05, top_h - 0.04);
  }
  void Chair(const Place& p) {
    const int id = NewObject("chair");
    const double s = Vary(0.45);
    Piece(id, p, 0, 0, 0.42, s, s, 0.05);
    Piece(id, p, 0, -s / 2 + 0.03, 0.47, s, 0.05, Vary(0.45));
    for (int i = 0; i < 4; ++i) Piece(id, p, (i % 2 ? 1 : -1) * (s / 2 - 0.03), (i / 2 ? 1 : -1) * (s / 2 - 0.03), 0, 0.04, 0.04, 0.42);
  }
  void Shelf(const Place& p) {
    const int id = NewObject("shelf");
    const double w = Vary(0.8), d = Vary(0.35), h = Vary(1.8);
    Piece(id, p, -w / 2, 0, 0, 0.03, d, h);
    Piece(id, p, w / 2, 0, 0, 0.03, d, h);
    for (int b = 0; b < 5; ++b) Piece(id, p, 0, 0, b * h / 4.5, w, d, 0.03);
  }
  void Cabinet(const Place& p, double w, double d, double h, double z0 = 0) { Piece(NewObject("cabinet"), p, 0, 0, z0, w, d, h); }
  void Clutter() {
    const Place p = Middle();
    Piece(NewObject("clutter"), p, 0, 0, 0, Vary(0.35), Vary(0.3), Vary(0.35));
  }

  std::mt19937_64& rng() { return rng_; }

 private:
  Room& room_;
  std::mt19937_64 rng_;
  std::vector<bool> against_wall_;  // per object id - 1
};

// The pieces of the room (RoomPiece): each object's primitives boxed in the frame of its first primitive.
std::vector<RoomPiece> RoomPieces(const Scene& scene, int structure, const RoomBuilder& b) {
  std::vector<RoomPiece> pieces;
  for (const Object& o : scene.objects) {
    if (o.id == structure) continue;
    RoomPiece piece;
    piece.object_id = o.id;
    piece.name = o.name;
    piece.against_wall = b.IsAgainstWall(o.id);
    bool first = true;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    Eigen::Matrix3d R_PieceWorld = Eigen::Matrix3d::Identity();
    for (const Primitive& p : scene.primitives) {
      if (p.object_id != o.id) continue;
      if (first) {
        const Eigen::Matrix3d R = p.X_WorldPrim.linear();
        piece.yaw_rad = std::atan2(R(1, 0), R(0, 0));
        R_PieceWorld = Eigen::AngleAxisd(-piece.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        first = false;
      }
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d c((corner & 1 ? 0.5 : -0.5) * p.size_m.x(), (corner & 2 ? 0.5 : -0.5) * p.size_m.y(),
                                (corner & 4 ? 0.5 : -0.5) * p.size_m.z());
        const Eigen::Vector3d in_piece = R_PieceWorld * (p.X_WorldPrim * c);
        lo = lo.cwiseMin(in_piece);
        hi = hi.cwiseMax(in_piece);
      }
    }
    if (first) continue;
    const Eigen::Vector3d mid = R_PieceWorld.transpose() * (0.5 * (lo + hi));
    piece.centre_m = mid.head<2>();
    piece.extent_m = (hi - lo).head<2>();
    piece.z0_m = lo.z();
    piece.height_m = hi.z() - lo.z();
    pieces.push_back(piece);
  }
  return pieces;
}

void Furnish(RoomBuilder& b, int category, const Eigen::Vector2d& size) {
  switch (category) {
    case 0: {  // bedroom: a bed with headboard, nightstands, a wardrobe
      const auto p = b.AgainstWall(2.0);
      const int bed = b.NewObject("bed");
      const double w = b.Vary(1.5);
      b.Piece(bed, p, 0, 0.0, 0, w, 2.0, b.Vary(0.5));
      b.Piece(bed, p, 0, -0.95, 0, w, 0.08, b.Vary(1.0));
      b.Piece(b.NewObject("nightstand"), p, w / 2 + 0.3, -0.75, 0, 0.45, 0.4, 0.5);
      if (b.Chance(0.7)) b.Piece(b.NewObject("nightstand"), p, -w / 2 - 0.3, -0.75, 0, 0.45, 0.4, 0.5);
      b.Cabinet(b.AgainstWall(0.6), b.Vary(1.2), 0.6, b.Vary(2.0));
      if (b.Chance(0.4)) b.Chair(b.Middle());
      break;
    }
    case 1: {  // dining room: a table with 4-6 chairs around it, a sideboard
      auto p = b.Middle();
      p.yaw = b.Chance(0.5) ? 0 : M_PI / 2;
      const double sx = b.Vary(1.6), sy = b.Vary(0.9);
      b.Table(p, b.Vary(0.75), sx, sy);
      const int chairs = 4 + static_cast<int>(b.rng()() % 3);
      for (int i = 0; i < chairs; ++i) {
        const double side = i % 2 ? 1 : -1;
        const double u = (static_cast<double>(i / 2) - (chairs / 2 - 1) / 2.0) * 0.6;
        RoomBuilder::Place c{p.At(u, side * (sy / 2 + 0.3)).x(), p.At(u, side * (sy / 2 + 0.3)).y(), p.yaw + (side > 0 ? M_PI : 0)};
        b.Chair(c);
      }
      if (b.Chance(0.7)) b.Cabinet(b.AgainstWall(0.45), b.Vary(1.6), 0.45, b.Vary(0.85));
      break;
    }
    case 2: {  // living room: a sofa, a coffee table, a tv on a low board, maybe an armchair and a shelf
      const auto s = b.AgainstWall(0.9, 0);
      const int sofa = b.NewObject("sofa");
      const double w = b.Vary(2.0);
      b.Piece(sofa, s, 0, 0.05, 0, w, 0.8, b.Vary(0.42));
      b.Piece(sofa, s, 0, -0.35, 0, w, 0.2, b.Vary(0.85));
      b.Piece(sofa, s, -w / 2, 0, 0, 0.2, 0.9, 0.6);
      b.Piece(sofa, s, w / 2, 0, 0, 0.2, 0.9, 0.6);
      b.Piece(b.NewObject("coffee table"), {s.x, s.y + 1.1, 0}, 0, 0, 0, b.Vary(1.0), b.Vary(0.55), b.Vary(0.4));
      const auto t = b.AgainstWall(0.4, 2);
      b.Cabinet(t, b.Vary(1.5), 0.4, b.Vary(0.5));
      b.Piece(b.NewObject("tv"), t, 0, 0, 0.55, b.Vary(1.1), 0.06, b.Vary(0.65));
      if (b.Chance(0.6)) b.Shelf(b.AgainstWall(0.35, 1));
      if (b.Chance(0.5)) b.Piece(b.NewObject("armchair"), b.Middle(), 0, 0, 0, 0.85, 0.85, 0.45);
      break;
    }
    case 3: {  // bathroom: a bath tub (a rim around a hollow), a toilet, a sink cabinet
      const auto p = b.AgainstWall(0.75);
      const int tub = b.NewObject("bath tub");
      const double l = b.Vary(1.7), h = b.Vary(0.55);
      b.Piece(tub, p, 0, -0.33, 0, l, 0.08, h);
      b.Piece(tub, p, 0, 0.33, 0, l, 0.08, h);
      b.Piece(tub, p, -l / 2, 0, 0, 0.08, 0.75, h);
      b.Piece(tub, p, l / 2, 0, 0, 0.08, 0.75, h);
      b.Piece(tub, p, 0, 0, 0, l, 0.75, 0.1);
      const auto t = b.AgainstWall(0.65);
      const int toilet = b.NewObject("toilet");
      b.Piece(toilet, t, 0, 0.05, 0, 0.38, 0.5, 0.4);
      b.Piece(toilet, t, 0, -0.25, 0, 0.4, 0.18, 0.8);
      const auto s = b.AgainstWall(0.45);
      b.Cabinet(s, b.Vary(0.6), 0.45, 0.85);
      b.Piece(b.NewObject("mirror"), s, 0, -0.2, 1.2, 0.6, 0.03, 0.7);
      break;
    }
    case 4: {  // office: a desk with a monitor, an office chair, shelves
      const auto d = b.AgainstWall(0.7);
      b.Table(d, b.Vary(0.73), b.Vary(1.4), 0.7);
      b.Piece(b.NewObject("monitor"), d, 0, -0.2, 0.75, b.Vary(0.55), 0.05, b.Vary(0.38));
      b.Chair({d.At(0, 0.7).x(), d.At(0, 0.7).y(), d.yaw + M_PI});
      b.Shelf(b.AgainstWall(0.35));
      if (b.Chance(0.6)) b.Shelf(b.AgainstWall(0.35));
      if (b.Chance(0.5)) b.Cabinet(b.AgainstWall(0.5), 0.45, 0.5, 0.65);
      break;
    }
    default: {  // kitchen: a counter run with upper cabinets, a refrigerator, maybe a small table and chair
      const int wall = static_cast<int>(b.rng()() % 4);
      const double along = (wall % 2 == 0 ? size.x() : size.y()) * b.Uniform(0.5, 0.8);
      auto p = b.AgainstWall(0.6, wall);
      const int counter = b.NewObject("kitchen counter");
      b.Piece(counter, p, 0, 0, 0, along, 0.6, 0.9);
      b.Piece(counter, p, 0, -0.12, 1.45, along, 0.35, b.Vary(0.7));
      b.Piece(b.NewObject("refrigerator"), p, along / 2 + 0.35, 0, 0, 0.6, 0.6, b.Vary(1.8));
      if (b.Chance(0.5)) {
        b.Table(b.Middle(), 0.75, b.Vary(0.9), b.Vary(0.7));
        b.Chair(b.Middle());
      }
      break;
    }
  }
  b.Clutter();
  if (b.Chance(0.5)) b.Clutter();
}

}  // namespace

const char* RoomCategoryName(int category) {
  static const char* kNames[kRoomCategoryCount] = {"bedroom", "dining_room", "living_room", "bathroom", "office", "kitchen"};
  return category >= 0 && category < kRoomCategoryCount ? kNames[category] : "?";
}

Room MakeRoom(int category, std::uint64_t seed) {
  Room room;
  room.category = category;
  RoomBuilder b(room, seed * 7919u + static_cast<std::uint64_t>(category));
  // Bathrooms are small, living rooms large.
  const double base[kRoomCategoryCount][2] = {{3.6, 3.4}, {3.8, 3.6}, {5.0, 4.2}, {2.4, 2.2}, {3.2, 3.0}, {3.4, 3.0}};
  room.size_m = Eigen::Vector2d(b.Vary(base[category][0]), b.Vary(base[category][1]));
  const double w = room.size_m.x(), h = room.size_m.y(), wall_h = 2.5;
  const int structure = b.NewObject("room");
  b.Box(structure, w / 2, h / 2, -0.05, w, h, 0.05, 0);  // floor
  b.Box(structure, w / 2, -0.05, 0, w + 0.2, 0.1, wall_h, 0);
  b.Box(structure, w / 2, h + 0.05, 0, w + 0.2, 0.1, wall_h, 0);
  b.Box(structure, -0.05, h / 2, 0, 0.1, h, wall_h, 0);
  b.Box(structure, w + 0.05, h / 2, 0, 0.1, h, wall_h, 0);
  Furnish(b, category, room.size_m);
  room.pieces = RoomPieces(room.scene, structure, b);
  // A robot in the middle scans the room: 6 keyframes, 60 deg apart, camera 1.2 m up looking 25 deg down.
  const Eigen::Vector3d eye(w / 2 + b.Uniform(-0.2, 0.2), h / 2 + b.Uniform(-0.2, 0.2), 1.2);
  for (int k = 0; k < 6; ++k) {
    const double a = k * M_PI / 3 + b.Uniform(-0.1, 0.1);
    room.X_WorldCamera.push_back(LookAt(eye, eye + Eigen::Vector3d(std::cos(a), std::sin(a), -std::tan(25 * M_PI / 180))));
  }
  return room;
}

}  // namespace anchordb::sim
