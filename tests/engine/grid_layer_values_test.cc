// How each layer kind reads as probabilities, and the statistics of a layer (engine/grid/layer_values.h).
#include "engine/grid/layer_values.h"

#include <gtest/gtest.h>

#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace grid_layer_values_test {

TEST(GridLayerValues, OccupancyReadsAsValueOverHundredAndUnknownAsHalf) {
  OccupancyGrid occupancy = testing::FreeGrid(5, 1, 1.0);
  occupancy.cells = {-1, 0, 25, 100, 127};
  const ProbabilityGrid p = OccupancyToProbability(occupancy);
  EXPECT_EQ(p.geometry, occupancy.geometry);
  EXPECT_EQ(p.cells, (std::vector<float>{0.5f, 0.0f, 0.25f, 1.0f, 1.0f}));
}

TEST(GridLayerValues, LabelsAndMasksReadAsZeroOrOne) {
  LabelGrid labels(testing::FreeGrid(3, 1, 1.0).geometry, 0);
  labels.cells = {0, 7, 65535};
  EXPECT_EQ(LabelsToProbability(labels).cells, (std::vector<float>{0.0f, 1.0f, 1.0f}));
  MaskGrid mask(labels.geometry, 0);
  mask.cells = {1, 0, 1};
  EXPECT_EQ(MaskToProbability(mask).cells, (std::vector<float>{1.0f, 0.0f, 1.0f}));
}

TEST(GridLayerValues, TrueCellsAreStrictlyAboveHalf) {
  ProbabilityGrid p(testing::FreeGrid(4, 1, 1.0).geometry, 0.0f);
  p.cells = {0.5f, 0.500001f, 1.0f, 0.0f};
  EXPECT_EQ(TrueCells(p).cells, (std::vector<std::uint8_t>{0, 1, 1, 0}));
}

TEST(GridLayerValues, OccupancyStatisticsFollowTheThresholds) {
  OccupancyGrid occupancy = testing::FreeGrid(6, 1, 1.0);
  occupancy.cells = {-1, 0, 25, 26, 64, 65};
  const OccupancyStatistics s = CountOccupancy(occupancy, OccupancyThresholds{});
  EXPECT_EQ(s.occupied_cells, 1u);  // 65
  EXPECT_EQ(s.free_cells, 2u);      // 0, 25
  EXPECT_EQ(s.unknown_cells, 3u);   // -1 and the values between the thresholds
  const OccupancyStatistics strict = CountOccupancy(occupancy, OccupancyThresholds{26, 0});
  EXPECT_EQ(strict.occupied_cells, 3u);
  EXPECT_EQ(strict.free_cells, 1u);
}

TEST(GridLayerValues, LabelStatisticsCountLabelledCellsOnly) {
  LabelGrid labels(testing::FreeGrid(5, 1, 1.0).geometry, 0);
  labels.cells = {0, 2, 2, 9, 0};
  const LabelStatistics s = CountLabels(labels);
  EXPECT_EQ(s.cells_per_label, (std::map<int, std::size_t>{{2, 2}, {9, 1}}));
}

TEST(GridLayerValues, ProbabilitySummaryCountsCellsStrictlyAboveHalf) {
  ProbabilityGrid p(testing::FreeGrid(4, 1, 1.0).geometry, 0.0f);
  p.cells = {0.5f, 0.25f, 0.75f, 1.0f};
  const ProbabilityStatistics s = SummariseProbability(p);
  EXPECT_DOUBLE_EQ(s.min_probability, 0.25);
  EXPECT_DOUBLE_EQ(s.max_probability, 1.0);
  EXPECT_DOUBLE_EQ(s.mean_probability, 0.625);
  EXPECT_EQ(s.cells_above_half, 2u);
}

TEST(GridLayerValues, ProbabilitySummaryOfAnEmptyGrid) {
  const ProbabilityStatistics s = SummariseProbability(ProbabilityGrid{});
  EXPECT_EQ(s.min_probability, 1.0);
  EXPECT_EQ(s.max_probability, 0.0);
  EXPECT_EQ(s.mean_probability, 0.0);
  EXPECT_EQ(s.cells_above_half, 0u);
}

}  // namespace
}  // namespace anchordb::engine
