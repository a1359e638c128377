// Observation semantics, cell by cell, on hand-made maps (thesis 3.4.2).
#include "engine/grid/observation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace {

using testing::OccupancyFromAscii;

Polygon2 Box(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

class ObservationTest : public ::testing::Test {
 protected:
  // 12 x 7 cells of 1 m. A wall at ix = 6 for iy in 2..4; the sensor at (1.5, 3.5) looks along +x.
  OccupancyGrid occupancy = OccupancyFromAscii({
      "............",
      "............",
      "......#.....",
      "......#.....",
      "......#.....",
      "............",
      "............",
  });
  LogOddsParams params;
  LogOddsModel model{params};
  OccupancyThresholds thresholds;
  LogOddsGrid layer{occupancy.geometry, 0.0f};

  Observation Look(double fov_rad, double range_m, std::vector<Polygon2> stimulus) {
    Observation o;
    o.sensor_position_m = {1.5, 3.5};
    o.heading_rad = 0.0;
    o.fov_rad = fov_rad;
    o.range_m = range_m;
    o.stimulus_M = std::move(stimulus);
    return o;
  }
};

TEST_F(ObservationTest, StimulusRaisedSeenLoweredWallAndShadowUnchanged) {
  // Stimulus: cells ix 3..4, iy 3 (centres (3.5, 3.5), (4.5, 3.5)).
  const auto counts = ApplyObservation(occupancy, thresholds, model, Look(M_PI / 2, 20.0, {Box(3.0, 3.0, 5.0, 4.0)}), layer);
  const float hit = ProbabilityToLogOdds(0.7), miss = ProbabilityToLogOdds(0.4);
  EXPECT_FLOAT_EQ(layer.at(3, 3), hit);
  EXPECT_FLOAT_EQ(layer.at(4, 3), hit);
  EXPECT_EQ(counts.raised, 2u);
  // Seen, not in the stimulus: lowered.
  EXPECT_FLOAT_EQ(layer.at(5, 3), miss);
  EXPECT_FLOAT_EQ(layer.at(2, 3), miss);
  EXPECT_FLOAT_EQ(layer.at(4, 4), miss);
  // The wall itself and the cells behind it on the line of sight: unchanged.
  EXPECT_FLOAT_EQ(layer.at(6, 3), 0.0f);
  EXPECT_FLOAT_EQ(layer.at(7, 3), 0.0f);
  EXPECT_FLOAT_EQ(layer.at(11, 3), 0.0f);
  EXPECT_FLOAT_EQ(layer.at(9, 4), 0.0f);
  // Beside the wall's end, not shadowed: seen.
  EXPECT_FLOAT_EQ(layer.at(8, 6), miss);
  // Behind the sensor (outside a 90 degree field of view): unchanged.
  EXPECT_FLOAT_EQ(layer.at(0, 3), 0.0f);
  EXPECT_FLOAT_EQ(layer.at(1, 0), 0.0f);
  EXPECT_GT(counts.unchanged_blocked, 0u);
}

TEST_F(ObservationTest, OutsideRangeAndFieldOfViewUnchanged) {
  ApplyObservation(occupancy, thresholds, model, Look(0.5, 3.0, {}), layer);
  const float miss = ProbabilityToLogOdds(0.4);
  EXPECT_FLOAT_EQ(layer.at(3, 3), miss);  // 2 m ahead
  EXPECT_FLOAT_EQ(layer.at(4, 3), miss);  // 3 m ahead: at the range
  EXPECT_FLOAT_EQ(layer.at(5, 3), 0.0f);  // 4 m: beyond range
  EXPECT_FLOAT_EQ(layer.at(3, 5), 0.0f);  // 45 degrees off: outside the 0.5 rad field of view
  EXPECT_FLOAT_EQ(layer.at(1, 3), miss);  // the sensor's own cell is seen
}

TEST_F(ObservationTest, StimulusBehindWallIsIgnoredAndReported) {
  const auto counts = ApplyObservation(occupancy, thresholds, model, Look(M_PI / 2, 20.0, {Box(8.0, 3.0, 9.0, 4.0)}), layer);
  EXPECT_FLOAT_EQ(layer.at(8, 3), 0.0f);
  EXPECT_EQ(counts.raised, 0u);
  EXPECT_EQ(counts.stimulus_outside_view, 1u);
}

TEST_F(ObservationTest, RepeatedHitsClampAtUpperBound) {
  for (int i = 0; i < 50; ++i) ApplyObservation(occupancy, thresholds, model, Look(M_PI / 2, 20.0, {Box(3.0, 3.0, 4.0, 4.0)}), layer);
  EXPECT_FLOAT_EQ(layer.at(3, 3), ProbabilityToLogOdds(0.97));
  EXPECT_FLOAT_EQ(layer.at(5, 3), ProbabilityToLogOdds(0.12));
  EXPECT_NEAR(LogOddsToProbability(layer.at(3, 3)), 0.97, 1e-6);
}

TEST_F(ObservationTest, UnknownCellsDoNotBlockSight) {
  OccupancyGrid unknown_wall = occupancy;
  for (int iy = 2; iy <= 4; ++iy) unknown_wall.at(6, iy) = -1;
  ApplyObservation(unknown_wall, thresholds, model, Look(M_PI / 2, 20.0, {}), layer);
  EXPECT_FLOAT_EQ(layer.at(7, 3), ProbabilityToLogOdds(0.4));
  EXPECT_FLOAT_EQ(layer.at(6, 3), ProbabilityToLogOdds(0.4));
}

TEST_F(ObservationTest, FullCircleSeesBehind) {
  ApplyObservation(occupancy, thresholds, model, Look(2 * M_PI, 20.0, {}), layer);
  EXPECT_FLOAT_EQ(layer.at(0, 3), ProbabilityToLogOdds(0.4));
}

TEST_F(ObservationTest, MismatchedGridsAreRejected) {
  LogOddsGrid other(testing::FreeGrid(5, 5, 1.0).geometry, 0.0f);
  EXPECT_THROW(ApplyObservation(occupancy, thresholds, model, Look(1.0, 3.0, {}), other), Error);
}

TEST(IsOccludedTest, DiagonalThroughCornerOfWall) {
  const OccupancyGrid grid = OccupancyFromAscii({
      ".....",
      ".....",
      "..#..",
      ".....",
      ".....",
  });
  OccupancyThresholds t;
  // From the centre of (0, 0) to (4, 4): the diagonal passes through the wall cell (2, 2).
  EXPECT_TRUE(IsOccluded(grid, t, {0.5, 0.5}, 4, 4));
  // To (4, 0) along the bottom row: clear.
  EXPECT_FALSE(IsOccluded(grid, t, {0.5, 0.5}, 4, 0));
  // The wall cell itself is not occluded by itself.
  EXPECT_FALSE(IsOccluded(grid, t, {0.5, 0.5}, 2, 2));
}

}  // namespace
}  // namespace anchordb::engine
