#pragma once
// The scenes of the merge robustness sweep (issue 13, anchordb_eval_merge --sweep): an object is added between a
// first viewpoint A and a second one B (the eye 0.45 m from A's, the heading turned by 35 deg, both looking down at
// the same table like a robot's head camera), and a third viewpoint C (the heading turned by 30 deg the other way)
// sees the scene as B did. World frame as in apartment.h (REP-103, z up; the room's inner wall faces at x = +-3 m,
// y = +-2.5 m, floor top z = 0). Units: metres, radians.
#include <Eigen/Geometry>
#include <cstdint>

#include "sim/renderer.h"

namespace anchordb::sim {

enum class SweepSceneKind {
  kSparse,     // the room, a table and one box on it: plane-dominated (floor, walls, table top)
  kCluttered,  // the tabletop setting of apartment.h (TA): a table with small objects, a chair, a plant, a bin
};

struct SweepScene {
  Scene before;       // seen from A
  Scene after;        // seen from B and C: `before` with the added object
  int added_id = 0;   // the object added between A and B (kind "movable")
  Eigen::Isometry3d X_WorldCameraA = Eigen::Isometry3d::Identity();  // optical frames in the world
  Eigen::Isometry3d X_WorldCameraB = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_WorldCameraC = Eigen::Isometry3d::Identity();
};

// Builds a sweep scene; `seed` varies the added object's size (+-10 %) and place on the table (+-5 cm) and, in the
// cluttered scene, the small objects as MakeSetting does. Same seed, same scene.
SweepScene MakeSweepScene(SweepSceneKind kind, std::uint64_t seed);

// "sparse" or "cluttered".
const char* SweepSceneName(SweepSceneKind kind);

}  // namespace anchordb::sim
