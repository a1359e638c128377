#include "tests/eval/mesh_rooms.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tests/eval/seeded_rng.h"

namespace anchordb::eval {
namespace {

// Which side of a mesh is its back, in the mesh's own frame (read off the files: a bed's headboard, a chair's or
// sofa's backrest, the door and drawer side of a wardrobe, nightstand and refrigerator is the front), or kNone for
// pieces without a front or whose front is not known (tables, desk, trash can; the shoe rack, the TV and the TV
// cabinet are taken as given), which stand with their longer side along the piece's.
enum Back { kNone, kPlusX, kPlusY, kMinusX, kMinusY };

struct Candidate {
  const char* file;
  Back back;
  bool into_corner = false;  // moved along the wall into the corner at the piece's own +x end
};

const Candidate kBed{"bed/Bed_01.obj", kPlusY};
const Candidate kNightstand{"nightstand/NightStand_01.obj", kPlusY};
const Candidate kWardrobe{"cupboard/Wardrobe_01.obj", kPlusY};
const Candidate kTvCabinet{"cupboard/TVCabinet_01.obj", kPlusX};
const Candidate kChairA{"chair/ChairA_01.obj", kPlusX};
const Candidate kChairD{"chair/ChairD_01.obj", kMinusX};
const Candidate kKitchenTable{"table/KitchenTable_01.obj", kNone};
const Candidate kBalconyTable{"table/BalconyTable_01.obj", kNone};
const Candidate kCoffeeTable{"table/CoffeeTable_01.obj", kNone};
const Candidate kDesk{"desk/ReadingDesk_01.obj", kNone};
// Sofa_01 and SofaC_01 are corner sofas (2.4 x 2.4 m), backs at +y and -x, the chaise at -x: in the corner, or the
// chaise would reach the middle of the room where the robot stands.
const Candidate kSofa{"sofa/Sofa_01.obj", kPlusY, true};
const Candidate kSofaC{"sofa/SofaC_01.obj", kPlusY, true};
const Candidate kArmchair{"sofa/SofaB_01.obj", kMinusX};
const Candidate kTv{"tv/TV_01.obj", kPlusX};
const Candidate kShelf{"shelf/ShoeRack_01.obj", kMinusY};
const Candidate kRefrigerator{"refrigerator/Refrigerator_01.obj", kPlusY};
const Candidate kTrashCan{"trash_can/Trash_01.obj", kNone};

// The meshes a box piece of a room category may become (empty: it stays a box). cupboard/KitchenCabinet_01 (an L
// of counter cabinets, 2.6 x 3.2 m) is not used: the kitchen counter is a box-built fixture.
std::vector<Candidate> CandidatesFor(const std::string& piece, int category, SeededRng& rng) {
  if (piece == "bed") return {kBed};
  if (piece == "nightstand") return {kNightstand};
  if (piece == "chair") return {kChairA, kChairD};
  if (piece == "sofa") return {kSofa, kSofaC};
  if (piece == "armchair") return {kArmchair};
  if (piece == "coffee table") return {kCoffeeTable, kBalconyTable};
  if (piece == "tv") return {kTv};
  if (piece == "shelf") return {kShelf};
  if (piece == "refrigerator") return {kRefrigerator};
  if (piece == "clutter") return rng.Chance(0.5) ? std::vector<Candidate>{kTrashCan} : std::vector<Candidate>{};
  if (piece == "table") {
    if (category == 4) return {kDesk};                  // the office's desk
    if (category == 1) return {kKitchenTable};          // the dining table
    return {kKitchenTable, kBalconyTable};              // the kitchen's small table
  }
  if (piece == "cabinet") {
    switch (category) {
      case 0: return {kWardrobe};                       // bedroom wardrobe
      case 1: case 2: return {kTvCabinet};              // dining room sideboard, living room TV board
      case 4: return {kNightstand};                     // the office's low drawer unit
      default: return {};                               // the bathroom's sink cabinet is a fixture
    }
  }
  return {};  // kitchen counter, bath tub, toilet, mirror, monitor
}

// Quarter turns from the piece's axes that bring the mesh's back to the piece's own -y (its wall side).
int QuarterTurns(Back back, const MeshBounds& b) {
  switch (back) {
    case kPlusX: return -1;
    case kPlusY: return 2;
    case kMinusX: return 1;
    case kMinusY: return 0;
    case kNone: break;
  }
  const Eigen::Vector3f size = b.hi - b.lo;
  return size.y() > size.x() ? -1 : 0;  // the longer side along the piece's own x
}

}  // namespace

std::vector<std::string> FurnitureMeshFiles() {
  std::vector<std::string> files;
  for (const Candidate& c : {kBed, kNightstand, kWardrobe, kTvCabinet, kChairA, kChairD, kKitchenTable, kBalconyTable,
                             kCoffeeTable, kDesk, kSofa, kSofaC, kArmchair, kTv, kShelf, kRefrigerator, kTrashCan}) {
    files.push_back(c.file);
  }
  return files;
}

std::optional<FurnitureMeshes> ReadFurnitureMeshes(const std::string& furniture_dir) {
  FurnitureMeshes out;
  for (const std::string& file : FurnitureMeshFiles()) {
    auto mesh = ReadObjFile(furniture_dir + "/" + file);
    if (!mesh) return std::nullopt;
    out.meshes.emplace(file, std::move(*mesh));
  }
  return out;
}

MeshRoom MakeMeshRoom(int category, std::uint64_t seed, const FurnitureMeshes& library) {
  MeshRoom out;
  out.room = sim::MakeRoom(category, seed);
  SeededRng rng(seed * 1000003u + static_cast<std::uint64_t>(category) * 7919u + 17u);
  const Eigen::Vector2d room_size = out.room.size_m;
  for (const sim::RoomPiece& piece : out.room.pieces) {
    const std::vector<Candidate> candidates = CandidatesFor(piece.name, category, rng);
    if (candidates.empty()) continue;
    const Candidate& c = candidates[candidates.size() == 1 ? 0 : static_cast<std::size_t>(rng.Below(static_cast<int>(candidates.size())))];
    const engine::TriangleMesh& mesh = library.meshes.at(c.file);
    const MeshBounds b = Bounds(mesh);
    MeshFit fit = FitMesh(b, QuarterTurns(c.back, b), piece.centre_m, piece.yaw_rad, piece.extent_m.y(),
                          piece.against_wall ? -1.0 : 0.0, piece.z0_m);
    if (c.into_corner) {  // the turn took the mesh's -x to the piece's +x; the clamp below stops it at the wall
      const Eigen::Vector2d own_x = Eigen::Rotation2Dd(piece.yaw_rad) * Eigen::Vector2d(1, 0);
      fit.centre_m += 100.0 * own_x;
      fit.X_WorldMesh.pretranslate(Eigen::Vector3d(100.0 * own_x.x(), 100.0 * own_x.y(), 0.0));
    }
    // Inside the room (2 cm from the walls): the footprint's world box shifted where it pokes through a wall.
    const double cy = std::abs(std::cos(piece.yaw_rad)), sy = std::abs(std::sin(piece.yaw_rad));
    const Eigen::Vector2d half(0.5 * (cy * fit.extent_m.x() + sy * fit.extent_m.y()),
                               0.5 * (sy * fit.extent_m.x() + cy * fit.extent_m.y()));
    Eigen::Vector2d shift = Eigen::Vector2d::Zero();
    for (int axis = 0; axis < 2; ++axis) {
      const double lo = 0.02 + half[axis], hi = room_size[axis] - 0.02 - half[axis];
      if (lo > hi) continue;  // larger than the room along this axis: left centred on its place
      shift[axis] = std::clamp(fit.centre_m[axis], lo, hi) - fit.centre_m[axis];
    }
    fit.centre_m += shift;
    fit.X_WorldMesh.pretranslate(Eigen::Vector3d(shift.x(), shift.y(), 0.0));
    sim::RemoveObject(out.room.scene, piece.object_id);
    out.meshes.push_back({&mesh, fit.X_WorldMesh});
    out.mesh_files.push_back(c.file);
    out.piece_names.push_back(piece.name);
  }
  return out;
}

}  // namespace anchordb::eval
