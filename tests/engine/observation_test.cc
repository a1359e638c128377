// Observation semantics, cell by cell, on hand-made maps (thesis 3.4.2), and the occlusion index against the
// per-cell traversal on seeded random maps.
#include "engine/grid/observation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "engine/grid/raster.h"
#include "engine/grid/visibility.h"
#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace observation_test {

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
    o.stimulus_map = std::move(stimulus);
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

// ---- Equivalence of the occlusion index with the per-cell traversal

// ApplyObservation as it was before the occlusion index: IsOccluded for every cell in view. The reference.
ObservationCounts ReferenceApplyObservation(const OccupancyGrid& occupancy, const OccupancyThresholds& t,
                                            const LogOddsModel& model, const Observation& obs, LogOddsGrid& log_odds) {
  const GridGeometry& g = log_odds.geometry;
  ObservationCounts counts;
  const Eigen::Vector2d sensor_grid = g.MapToGrid(obs.sensor_position_m);
  const double range_cells = obs.range_m / g.resolution_m;
  const int ix0 = std::max(0, static_cast<int>(std::floor(sensor_grid.x() - range_cells)));
  const int ix1 = std::min(g.width_cells - 1, static_cast<int>(std::ceil(sensor_grid.x() + range_cells)));
  const int iy0 = std::max(0, static_cast<int>(std::floor(sensor_grid.y() - range_cells)));
  const int iy1 = std::min(g.height_cells - 1, static_cast<int>(std::ceil(sensor_grid.y() + range_cells)));
  MaskGrid stimulus(g, 0);
  const std::size_t stimulus_cells = RasterisePolygons(obs.stimulus_map, stimulus);
  std::size_t stimulus_seen = 0;
  const double half_fov = obs.fov_rad / 2.0;
  const bool full_circle = obs.fov_rad >= 2.0 * std::numbers::pi - 1e-9;
  const double heading_grid = obs.heading_rad - g.origin_yaw_rad;
  const double range_sq = range_cells * range_cells;
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      const double dx = ix + 0.5 - sensor_grid.x(), dy = iy + 0.5 - sensor_grid.y();
      if (dx * dx + dy * dy > range_sq) continue;
      if (!full_circle && (dx != 0 || dy != 0)) {
        const double angle = std::remainder(std::atan2(dy, dx) - heading_grid, 2.0 * std::numbers::pi);
        if (std::abs(angle) > half_fov) continue;
      }
      if (IsOccupied(occupancy.at(ix, iy), t) || IsOccluded(occupancy, t, sensor_grid, ix, iy)) {
        ++counts.unchanged_blocked;
        continue;
      }
      float& l = log_odds.at(ix, iy);
      if (stimulus.at(ix, iy)) {
        l = model.Raise(l);
        ++counts.raised;
        ++stimulus_seen;
      } else {
        l = model.Lower(l);
        ++counts.lowered;
      }
    }
  }
  counts.stimulus_outside_view = stimulus_cells - stimulus_seen;
  return counts;
}

// Kinds of random occupancy: what makes the traversal's corner rules matter is in each of them.
enum class Scene { kSparse, kDense, kWalls, kRooms, kSingleCells, kCheckerboard, kDiagonals, kEmpty };
constexpr int kSceneKinds = 8;

// Occupied values span [65, 100], free ones [0, 64] (64 does not block), unknown is -1 (does not block).
OccupancyGrid RandomScene(std::mt19937& rng, Scene scene, int width, int height, double resolution_m) {
  GridGeometry g;
  g.width_cells = width;
  g.height_cells = height;
  g.resolution_m = resolution_m;
  OccupancyGrid grid(g, 0);
  std::uniform_int_distribution<int> free_value(0, 64), occupied_value(65, 100), x_of(0, width - 1),
      y_of(0, height - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto& v : grid.cells) v = static_cast<std::int8_t>(unit(rng) < 0.1 ? -1 : free_value(rng));
  const auto occupy = [&](int x, int y) {
    if (g.Contains(x, y)) grid.at(x, y) = static_cast<std::int8_t>(occupied_value(rng));
  };
  const int area = width * height;
  switch (scene) {
    case Scene::kSparse:
    case Scene::kDense: {
      const double density = scene == Scene::kSparse ? 0.03 : 0.35;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          if (unit(rng) < density) occupy(x, y);
        }
      }
      break;
    }
    case Scene::kWalls:
      for (int w = 0; w < 2 + area / 200; ++w) {
        const int x = x_of(rng), y = y_of(rng), length = 2 + static_cast<int>(unit(rng) * width);
        const bool vertical = unit(rng) < 0.5;
        const int thickness = 1 + static_cast<int>(unit(rng) * 3);
        for (int k = 0; k < length; ++k) {
          if (unit(rng) < 0.05) continue;  // a gap
          for (int d = 0; d < thickness; ++d) vertical ? occupy(x + d, y + k) : occupy(x + k, y + d);
        }
      }
      break;
    case Scene::kRooms:
      for (int r = 0; r < 1 + area / 400; ++r) {
        const int x0 = x_of(rng), y0 = y_of(rng);
        const int x1 = x0 + 3 + static_cast<int>(unit(rng) * width / 2);
        const int y1 = y0 + 3 + static_cast<int>(unit(rng) * height / 2);
        for (int x = x0; x <= x1; ++x) {
          if (unit(rng) > 0.1) occupy(x, y0);
          if (unit(rng) > 0.1) occupy(x, y1);
        }
        for (int y = y0; y <= y1; ++y) {
          if (unit(rng) > 0.1) occupy(x0, y);
          if (unit(rng) > 0.1) occupy(x1, y);
        }
      }
      break;
    case Scene::kSingleCells:
      for (int k = 0; k < 1 + area / 150; ++k) occupy(x_of(rng), y_of(rng));
      break;
    case Scene::kCheckerboard: {
      // Cells touching at corners only: rays through those corners pass or not by the traversal's tie rule.
      const int x0 = x_of(rng), y0 = y_of(rng), size = 2 + static_cast<int>(unit(rng) * 8);
      for (int y = y0; y < y0 + size; ++y) {
        for (int x = x0; x < x0 + size; ++x) {
          if ((x + y) % 2 == 0) occupy(x, y);
        }
      }
      break;
    }
    case Scene::kDiagonals:
      for (int d = 0; d < 1 + area / 300; ++d) {
        const int x = x_of(rng), y = y_of(rng), length = 2 + static_cast<int>(unit(rng) * width);
        const int sx = unit(rng) < 0.5 ? 1 : -1;
        for (int k = 0; k < length; ++k) occupy(x + sx * k, y + k);
      }
      break;
    case Scene::kEmpty:
      break;
  }
  return grid;
}

// Sensor positions in continuous grid coordinates: random, exact cell centres (45 degree diagonals to other
// centres pass exactly through cell corners), exact corners, on a grid line, a hair beside a corner, just off
// the grid.
Eigen::Vector2d RandomSensorGrid(std::mt19937& rng, int kind, int width, int height) {
  std::uniform_real_distribution<double> x_of(0.0, width), y_of(0.0, height);
  std::uniform_int_distribution<int> ix_of(0, width - 1), iy_of(0, height - 1), sign(0, 1);
  switch (kind) {
    case 0: return {x_of(rng), y_of(rng)};
    case 1: return {ix_of(rng) + 0.5, iy_of(rng) + 0.5};
    case 2: return {ix_of(rng) + 1.0, iy_of(rng) + 1.0};
    case 3: {  // on a vertical or a horizontal grid line, level with cell centres or not
      const double along = sign(rng) ? 0.5 : 0.25;
      if (sign(rng)) return {static_cast<double>(ix_of(rng)), iy_of(rng) + along};
      return {ix_of(rng) + along, static_cast<double>(iy_of(rng))};
    }
    case 4: return {ix_of(rng) + 1.0 + (sign(rng) ? 1e-12 : -1e-12), iy_of(rng) + 1.0 + (sign(rng) ? 1e-9 : -1e-9)};
    default: return {sign(rng) ? -0.75 : width + 0.5, y_of(rng)};
  }
}
constexpr int kSensorKinds = 6;

TEST(ObservationEquivalenceTest, IndexedUpdateEqualsPerCellTraversalOnRandomScenes) {
  std::mt19937 rng(20250117u);
  const LogOddsModel model{LogOddsParams{}};
  const OccupancyThresholds thresholds;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 1200; ++trial) {
    const Scene scene = static_cast<Scene>(trial % kSceneKinds);
    const int sensor_kind = (trial / kSceneKinds) % kSensorKinds;
    const bool large = trial % 25 == 0;
    const int width = large ? 160 : 6 + static_cast<int>(unit(rng) * 40);
    const int height = large ? 140 : 6 + static_cast<int>(unit(rng) * 40);
    // Resolution 1 m and a zero origin keep map and grid coordinates exactly equal; a few grids are finer.
    const double resolution_m = trial % 7 == 3 ? 0.05 : 1.0;
    const OccupancyGrid occupancy = RandomScene(rng, scene, width, height, resolution_m);
    const Eigen::Vector2d sensor_grid = RandomSensorGrid(rng, sensor_kind, width, height);
    Observation obs;
    obs.sensor_position_m = sensor_grid * resolution_m;
    obs.heading_rad = unit(rng) * 2.0 * std::numbers::pi - std::numbers::pi;
    obs.fov_rad = trial % 3 == 0 ? 0.1 + unit(rng) * 6.0 : 2.0 * std::numbers::pi;
    obs.range_m = (1.0 + unit(rng) * (large ? 120.0 : 40.0)) * resolution_m;
    const Eigen::Vector2d c = Eigen::Vector2d(unit(rng) * width, unit(rng) * height) * resolution_m;
    const double half_m = (1.0 + unit(rng) * 6.0) * resolution_m;
    obs.stimulus_map = {Box(c.x() - half_m, c.y() - half_m, c.x() + half_m, c.y() + half_m)};

    LogOddsGrid expected(occupancy.geometry, 0.0f);
    std::uniform_real_distribution<float> initial(model.min, model.max);
    for (float& l : expected.cells) l = initial(rng);
    LogOddsGrid actual = expected;
    const ObservationCounts want = ReferenceApplyObservation(occupancy, thresholds, model, obs, expected);
    const ObservationCounts got = ApplyObservation(occupancy, thresholds, model, obs, actual);
    const std::string where = "trial " + std::to_string(trial) + ": scene " + std::to_string(static_cast<int>(scene)) +
                              ", sensor kind " + std::to_string(sensor_kind) + " at (" +
                              std::to_string(sensor_grid.x()) + ", " + std::to_string(sensor_grid.y()) + ")";
    ASSERT_EQ(got.raised, want.raised) << where;
    ASSERT_EQ(got.lowered, want.lowered) << where;
    ASSERT_EQ(got.unchanged_blocked, want.unchanged_blocked) << where;
    ASSERT_EQ(got.stimulus_outside_view, want.stimulus_outside_view) << where;
    for (int iy = 0; iy < height; ++iy) {
      for (int ix = 0; ix < width; ++ix) {
        ASSERT_EQ(actual.at(ix, iy), expected.at(ix, iy)) << where << ", cell (" << ix << ", " << iy << ")";
      }
    }
    compared += want.unchanged_blocked > 0 && want.lowered > 0;
  }
  EXPECT_GT(compared, 600);  // most trials see both blocked and seen cells
}

TEST(ObservationEquivalenceTest, OcclusionIndexEqualsTraversalOnEveryCellInRange) {
  // Occupied targets too, and every sensor kind on every scene kind.
  std::mt19937 rng(777u);
  const OccupancyThresholds thresholds;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t occluded = 0, visible = 0;
  for (int trial = 0; trial < kSceneKinds * kSensorKinds * 8; ++trial) {
    const Scene scene = static_cast<Scene>(trial % kSceneKinds);
    const int sensor_kind = (trial / kSceneKinds) % kSensorKinds;
    const int width = 8 + static_cast<int>(unit(rng) * 40), height = 8 + static_cast<int>(unit(rng) * 40);
    const OccupancyGrid occupancy = RandomScene(rng, scene, width, height, 1.0);
    const Eigen::Vector2d sensor_grid = RandomSensorGrid(rng, sensor_kind, width, height);
    const double range_cells = 2.0 + unit(rng) * 50.0;
    OcclusionIndex index(occupancy, thresholds, sensor_grid, range_cells);
    for (int iy = 0; iy < height; ++iy) {
      for (int ix = 0; ix < width; ++ix) {
        const double dx = ix + 0.5 - sensor_grid.x(), dy = iy + 0.5 - sensor_grid.y();
        if (dx * dx + dy * dy > range_cells * range_cells) continue;
        const bool want = IsOccluded(occupancy, thresholds, sensor_grid, ix, iy);
        ASSERT_EQ(index.IsOccluded(ix, iy), want)
            << "trial " << trial << ", sensor (" << sensor_grid.x() << ", " << sensor_grid.y() << "), cell (" << ix
            << ", " << iy << ")";
        (want ? occluded : visible) += 1;
      }
    }
  }
  EXPECT_GT(occluded, 10000u);
  EXPECT_GT(visible, 10000u);
}

TEST(ObservationEquivalenceTest, TieRulesAtExactCorners) {
  // The traversal steps in y first when a segment meets a corner exactly. From the corner (2, 2) towards the
  // lower left it therefore visits (2, 1) before (1, 1); from the centre of (0, 0) along the diagonal it visits
  // (0, 1) between (0, 0) and (1, 1). The index must reproduce both.
  OccupancyGrid grid = OccupancyFromAscii({
      ".....",
      ".....",
      ".....",
      "..#..",
      ".....",
  });
  const OccupancyThresholds t;
  OcclusionIndex from_corner(grid, t, {2.0, 2.0}, 5.0);
  EXPECT_TRUE(IsOccluded(grid, t, {2.0, 2.0}, 0, 0));
  EXPECT_TRUE(from_corner.IsOccluded(0, 0));
  EXPECT_FALSE(from_corner.IsOccluded(4, 4));
  grid = OccupancyFromAscii({
      ".....",
      ".....",
      ".....",
      "#....",
      ".....",
  });
  OcclusionIndex from_centre(grid, t, {0.5, 0.5}, 6.0);
  EXPECT_TRUE(IsOccluded(grid, t, {0.5, 0.5}, 3, 3));
  EXPECT_TRUE(from_centre.IsOccluded(3, 3));
  EXPECT_FALSE(from_centre.IsOccluded(3, 0));
  // Mirrored: the wall at (1, 0) is skipped on the way up the diagonal.
  grid = OccupancyFromAscii({
      ".....",
      ".....",
      ".....",
      ".....",
      ".#...",
  });
  OcclusionIndex mirrored(grid, t, {0.5, 0.5}, 6.0);
  EXPECT_FALSE(IsOccluded(grid, t, {0.5, 0.5}, 3, 3));
  EXPECT_FALSE(mirrored.IsOccluded(3, 3));
}

}  // namespace
}  // namespace anchordb::engine
