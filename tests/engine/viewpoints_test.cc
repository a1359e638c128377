// Attention and observation viewpoints (thesis 3.4.3) on a constructed room.
#include "engine/grid/viewpoints.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/grid/attention.h"
#include "engine/grid/regions.h"
#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace viewpoints_test {

constexpr double kRes = 0.05;

// A 10 m x 8 m room with outer walls, a 1.2 m x 0.8 m table centred at (5, 4) (the table is not an obstacle in
// the laser map: only its legs would be), and a closed closet whose walls enclose x 6.4..7.6, y 3.0..5.0.
struct Room {
  OccupancyGrid occupancy = testing::FreeGrid(200, 160, kRes);
  MaskGrid surface{occupancy.geometry, 0};

  Room() {
    auto& g = occupancy.geometry;
    for (int ix = 0; ix < g.width_cells; ++ix) occupancy.at(ix, 0) = occupancy.at(ix, g.height_cells - 1) = 100;
    for (int iy = 0; iy < g.height_cells; ++iy) occupancy.at(0, iy) = occupancy.at(g.width_cells - 1, iy) = 100;
    auto cell = [](double m) { return static_cast<int>(std::floor(m / kRes)); };
    for (int ix = cell(6.4); ix <= cell(7.6); ++ix) occupancy.at(ix, cell(3.0)) = occupancy.at(ix, cell(5.0)) = 100;
    for (int iy = cell(3.0); iy <= cell(5.0); ++iy) occupancy.at(cell(6.4), iy) = occupancy.at(cell(7.6), iy) = 100;
    for (int iy = cell(3.6); iy < cell(4.4); ++iy) for (int ix = cell(4.4); ix < cell(5.6); ++ix) surface.at(ix, iy) = 1;
  }
  bool InCloset(const Eigen::Vector2d& p) const { return p.x() > 6.4 && p.x() < 7.65 && p.y() > 3.0 && p.y() < 5.05; }
};

Agent PersonSouthOfTableFacingIt() {
  Agent a;
  a.id = "p";
  a.position_m = {5.0, 3.2};
  a.heading_rad = M_PI / 2;
  return a;
}

TEST(ViewpointsTest, EveryViewpointIsFreeReachableAtDistanceAndBesideBeatsBehind) {
  Room room;
  const Agent person = PersonSouthOfTableFacingIt();
  ViewpointOptions options;
  options.max_viewpoints = 100;
  const Eigen::Vector2d robot{1.0, 1.0};
  const ViewpointPlan plan = PlanViewpoints(room.occupancy, room.surface, robot, person, options);
  ASSERT_GE(plan.viewpoints.size(), 4u);
  EXPECT_GT(plan.boundary_cells, plan.candidate_cells);  // the filters removed something (walls, closet, person)
  const auto& g = room.occupancy.geometry;
  const Eigen::Vector2d robot_grid = g.MapToGrid(robot);
  const auto travel = TravelDistances(room.occupancy, options.occupancy, static_cast<int>(robot_grid.x()),
                                      static_cast<int>(robot_grid.y()), options.robot_radius_m);
  double worst_beside = 1e9, best_behind = -1e9;
  int beside = 0, behind = 0;
  for (const Viewpoint& v : plan.viewpoints) {
    const Eigen::Vector2d q = g.MapToGrid(v.position_m);
    const int ix = static_cast<int>(q.x()), iy = static_cast<int>(q.y());
    EXPECT_TRUE(IsFree(room.occupancy.at(ix, iy), options.occupancy));
    EXPECT_TRUE(std::isfinite(travel[iy * g.width_cells + ix])) << v.position_m.transpose();
    EXPECT_FALSE(room.InCloset(v.position_m)) << v.position_m.transpose();
    EXPECT_GE(v.surface_distance_m, 0.5);
    EXPECT_LE(v.surface_distance_m, 2.0);
    EXPECT_GE(v.person_distance_m, 0.5);
    if (v.relation == "beside") worst_beside = std::min(worst_beside, v.score), ++beside;
    if (v.relation == "behind") best_behind = std::max(best_behind, v.score), ++behind;
  }
  ASSERT_GT(beside, 0);
  ASSERT_GT(behind, 0);
  EXPECT_GT(worst_beside, best_behind);
  for (std::size_t i = 1; i < plan.viewpoints.size(); ++i) EXPECT_GE(plan.viewpoints[i - 1].score, plan.viewpoints[i].score);
}

TEST(ViewpointsTest, DeterministicForOneSeed) {
  Room room;
  const Agent person = PersonSouthOfTableFacingIt();
  ViewpointOptions options;
  const auto a = PlanViewpoints(room.occupancy, room.surface, {1.0, 1.0}, person, options);
  const auto b = PlanViewpoints(room.occupancy, room.surface, {1.0, 1.0}, person, options);
  ASSERT_EQ(a.viewpoints.size(), b.viewpoints.size());
  for (std::size_t i = 0; i < a.viewpoints.size(); ++i) EXPECT_EQ(a.viewpoints[i].position_m, b.viewpoints[i].position_m);
}

TEST(ViewpointsTest, RobotInsideAWallIsRejected) {
  Room room;
  EXPECT_THROW(PlanViewpoints(room.occupancy, room.surface, {0.01, 0.01}, PersonSouthOfTableFacingIt(), {}), Error);
}

TEST(ViewpointsTest, PositionScoreOrdersBesideFrontBehind) {
  EXPECT_DOUBLE_EQ(PositionScore(M_PI / 2), 1.0);
  EXPECT_NEAR(PositionScore(M_PI), 0.0, 1e-12);
  // Every beside angle beats every in-front angle, which beats every behind angle.
  double min_beside = 2, max_front = -1, min_front = 2, max_behind = -1;
  for (int deg = 0; deg <= 180; ++deg) {
    const double s = PositionScore(deg * M_PI / 180.0);
    if (deg < 45) max_front = std::max(max_front, s), min_front = std::min(min_front, s);
    else if (deg <= 135) min_beside = std::min(min_beside, s);
    else max_behind = std::max(max_behind, s);
  }
  EXPECT_GT(min_beside, max_front);
  EXPECT_GT(min_front, max_behind);
}

TEST(TravelDistancesTest, ShortestPathAroundAWallAndClosedRoomsUnreachable) {
  const OccupancyGrid grid = testing::OccupancyFromAscii({
      "#######",
      "#.....#",
      "#.###.#",
      "#.#.#.#",
      "#.###.#",
      "#.....#",
      "#######",
  });
  const auto d = TravelDistances(grid, {}, 1, 1, 0.0);
  EXPECT_DOUBLE_EQ(d[1 * 7 + 1], 0.0);
  EXPECT_DOUBLE_EQ(d[1 * 7 + 5], 4.0);                  // straight along the bottom corridor
  EXPECT_NEAR(d[5 * 7 + 5], 8.0, 1e-9);                 // around the box: no cutting past wall corners
  EXPECT_TRUE(std::isinf(d[3 * 7 + 3]));                // the enclosed cell
}

TEST(AttentionTest, NextToAndFacingVersusAwayOrFar) {
  Room room;
  ProbabilityGrid p(room.occupancy.geometry, 0.0f);
  for (std::size_t i = 0; i < p.cells.size(); ++i) p.cells[i] = room.surface.cells[i] ? 0.9f : 0.1f;
  const auto regions = ExtractRegions(p, 0.5, 0.0);
  ASSERT_EQ(regions.size(), 1u);
  AttentionOptions options;
  Agent person = PersonSouthOfTableFacingIt();
  auto r = ComputeAttention(person, regions, p.geometry, options);
  EXPECT_TRUE(r.attending);
  ASSERT_TRUE(r.attended.has_value());
  EXPECT_EQ(r.attended->region_id, 1);
  EXPECT_NEAR(r.attended->distance_m, 3.6 - 3.2, 0.06);  // to the nearest table cell centre
  person.heading_rad = -M_PI / 2;  // turned away
  EXPECT_FALSE(ComputeAttention(person, regions, p.geometry, options).attending);
  person = PersonSouthOfTableFacingIt();
  person.position_m = {5.0, 1.5};  // facing it, but 2 m away
  r = ComputeAttention(person, regions, p.geometry, options);
  EXPECT_FALSE(r.attending);
  EXPECT_FALSE(r.relations.front().near);
  EXPECT_TRUE(r.relations.front().facing);
}

}  // namespace
}  // namespace anchordb::engine
