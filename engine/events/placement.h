#pragma once
// Where an object is, in words (SPEC §4.4, thesis 5.3.5): the nearest furniture piece and the relation of the
// object to it. An object standing inside a piece's footprint is "on" it; otherwise the relation is the relative
// one seen from a viewer (left_of / right_of / in_front_of / behind, as the grounding model defines them). Which
// word a listener would use (relative or intrinsic frame) is the grounding model's choice and is made by the caller.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "engine/grounding/furniture_graph.h"

namespace anchordb::engine {

struct FurniturePiece {
  std::string id;
  std::string name;                                     // what the robot calls it ("table")
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // footprint centre in the map frame
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();    // along its own axes
  double yaw_rad = 0.0;
};

struct Placement {
  int piece = -1;                 // index into the pieces; -1 when there are none
  bool on = false;                // inside the footprint (within `on_margin_m`)
  grounding::Relation relative = grounding::Relation::kLeftOf;  // seen from the viewer, when not `on`
  double gap_m = 0.0;             // distance from the footprint's edge (0 when on)
};

// Distance from p to the piece's footprint (0 inside).
double FootprintDistance(const FurniturePiece& piece, const Eigen::Vector2d& p_m);

Placement PlaceObject(const Eigen::Vector3d& object_m, const std::vector<FurniturePiece>& pieces,
                      const grounding::Viewpoint& viewer, double on_margin_m = 0.03);

}  // namespace anchordb::engine
