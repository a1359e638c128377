#pragma once
// The initial orientation p(o) of furniture from the room around it (issue 17), instead of the thesis' uniform one:
// each category's FrontPrior (categories.json "front") says where its pieces tend to face - a shelf, wardrobe,
// cupboard or chest of drawers with its back to the nearest wall of the occupancy layer, a chair towards the table
// it stands at, a sofa or armchair into the room. A piece gets the rule of its most probable category f:
//   p(o) = w_f q(o) + (1 - w_f) / 4,
// where q(o) ∝ exp(kappa cos(angle between the rule's front direction and o's direction, seen from the viewpoint))
// and w_f the rule's weight; a rule that finds nothing (no wall or piece within reach, no occupancy layer for
// back_to_wall) gives the uniform distribution, as do categories without a rule. (A mixture over p(f) was tried:
// at quality-A p(f) it dilutes the shelf's prior to 0.68 in the rendered room, and the prior is only where the
// descriptions start.)
//
// Frames: positions in the map frame M [m]; orientations as in knowledge.h (front = facing the viewer).
#include <Eigen/Core>

#include <optional>
#include <vector>

#include "engine/grid/grid.h"
#include "engine/grounding/furniture_graph.h"

namespace anchordb::engine::grounding {

struct RoomLayout {
  const OccupancyGrid* occupancy = nullptr;  // the map's occupancy layer, or none
  OccupancyThresholds thresholds;
};

// kappa of q(o): 0.995 on the orientation of a direction seen head-on, 0.82 on the nearer of two orientations 35
// and 55 degrees away (an oblique view; the four orientations are 90 degrees apart).
inline constexpr double kFrontSharpness = 6.0;

// p(o) of a piece whose front points along front_map (map frame, any length > 0), seen from `viewpoint`.
Distribution4 OrientationFromFront(const Viewpoint& viewpoint, const Eigen::Vector2d& front_map, double kappa);

// The direction piece `i`'s front points by `rule` (map frame, unit), or nullopt when the rule finds nothing.
std::optional<Eigen::Vector2d> FrontDirection(const FrontPrior& rule, std::size_t i, const std::vector<FurnitureInput>& furniture,
                                              const CategoryTable& categories, const RoomLayout& room);

// The prior of every piece, vertices x 4 (the layout of GraphState::orientation).
std::vector<double> RoomOrientationPrior(const Viewpoint& viewpoint, const std::vector<FurnitureInput>& furniture,
                                         const CategoryTable& categories, const RoomLayout& room);

}  // namespace anchordb::engine::grounding
