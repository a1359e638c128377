#pragma once
// The rooms of sim/rooms.h furnished from the real furniture meshes of ../shared/data/aws_small_house/
// furniture_converted (issue 15): the box room's layout (sim::MakeRoom) with each piece whose kind has a mesh
// replaced by a mesh of that kind, chosen per piece by a seeded RNG of the room where the kind has several; fixtures
// without a mesh (kitchen counter, bath tub, toilet, sink cabinet, mirror, monitor) and half of the clutter stay
// boxes. A mesh stands on the piece's footprint centre, turned so that its back faces the piece's wall (or, for
// pieces without a front, its longer side along the piece's), moved back to that wall and kept inside the room.
// The mesh code lives here, not in sim/, because sim/ may not use engine/ (sim/README.md).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/rooms.h"
#include "tests/eval/mesh_furniture.h"

namespace anchordb::eval {

// Every mesh the mesh rooms use, by its path below the furniture folder ("bed/Bed_01.obj").
struct FurnitureMeshes {
  std::map<std::string, engine::TriangleMesh> meshes;
};
// Reads them from `furniture_dir` (…/aws_small_house/furniture_converted); nullopt when one is missing.
std::optional<FurnitureMeshes> ReadFurnitureMeshes(const std::string& furniture_dir);
// The paths ReadFurnitureMeshes reads.
std::vector<std::string> FurnitureMeshFiles();

struct MeshRoom {
  sim::Room room;                        // the box room without the replaced pieces (their RoomPiece entries stay)
  std::vector<PlacedMesh> meshes;        // pointing into the FurnitureMeshes given
  std::vector<std::string> mesh_files;   // per mesh
  std::vector<std::string> piece_names;  // per mesh: the box piece it replaced
};

// The room of sim::MakeRoom(category, seed) furnished with `library`'s meshes. Seeded: same inputs, same room.
MeshRoom MakeMeshRoom(int category, std::uint64_t seed, const FurnitureMeshes& library);

}  // namespace anchordb::eval
