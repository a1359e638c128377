#include "engine/grid/regions.h"

#include <gtest/gtest.h>

#include "engine/grid/fusion.h"
#include "engine/grid/raster.h"
#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace regions_test {

ProbabilityGrid Blobs() {
  GridGeometry g;
  g.width_cells = 40;
  g.height_cells = 30;
  g.resolution_m = 0.1;
  g.origin_x_m = -1.0;
  g.origin_y_m = 2.0;
  ProbabilityGrid p(g, 0.1f);
  for (int iy = 5; iy < 15; ++iy) for (int ix = 5; ix < 25; ++ix) p.at(ix, iy) = 0.9f;   // 20 x 10 cells
  for (int iy = 20; iy < 23; ++iy) for (int ix = 30; ix < 33; ++ix) p.at(ix, iy) = 0.7f; // 3 x 3 cells
  p.at(0, 29) = 0.6f;                                                                    // a single cell
  return p;
}

TEST(RegionsTest, AreaCentroidPolygonAndOrder) {
  const auto regions = ExtractRegions(Blobs(), 0.5, 0.0);
  ASSERT_EQ(regions.size(), 3u);
  EXPECT_EQ(regions[0].id, 1);
  EXPECT_EQ(regions[0].cell_count, 200u);
  EXPECT_NEAR(regions[0].area_m2, 2.0, 1e-9);
  // Centre of cells 5..24 x 5..14 at 0.1 m from origin (-1, 2): x = -1 + 1.5, y = 2 + 1.0
  EXPECT_NEAR(regions[0].centroid_m.x(), 0.5, 1e-9);
  EXPECT_NEAR(regions[0].centroid_m.y(), 3.0, 1e-9);
  EXPECT_NEAR(regions[0].mean_probability, 0.9, 1e-6);
  ASSERT_EQ(regions[0].polygon_m.size(), 4u);  // an axis-aligned rectangle through boundary cell centres
  for (const auto& v : regions[0].polygon_m) {
    EXPECT_TRUE(std::abs(v.x() - (-0.45)) < 1e-9 || std::abs(v.x() - 1.45) < 1e-9);
    EXPECT_TRUE(std::abs(v.y() - 2.55) < 1e-9 || std::abs(v.y() - 3.45) < 1e-9);
  }
  EXPECT_EQ(regions[1].cell_count, 9u);
  EXPECT_EQ(regions[2].cell_count, 1u);
}

TEST(RegionsTest, ThresholdAndMinimumArea) {
  EXPECT_EQ(ExtractRegions(Blobs(), 0.65, 0.0).size(), 2u);
  EXPECT_EQ(ExtractRegions(Blobs(), 0.5, 0.05).size(), 2u);
  EXPECT_EQ(ExtractRegions(Blobs(), 0.95, 0.0).size(), 0u);
}

TEST(RegionsTest, DiagonalNeighboursJoinOneRegion) {
  GridGeometry g;
  g.width_cells = g.height_cells = 4;
  g.resolution_m = 1.0;
  ProbabilityGrid p(g, 0.0f);
  p.at(0, 0) = p.at(1, 1) = p.at(2, 2) = 1.0f;
  EXPECT_EQ(ExtractRegions(p, 0.5, 0.0).size(), 1u);
}

TEST(FusionTest, OperatorsCellByCell) {
  GridGeometry g;
  g.width_cells = 4;
  g.height_cells = 1;
  ProbabilityGrid a(g, 0.0f), b(g, 0.0f);
  a.cells = {0.9f, 0.9f, 0.1f, 0.1f};
  b.cells = {0.9f, 0.1f, 0.9f, 0.1f};
  const std::vector<MaskGrid> ops = {Threshold(a, 0.5), Threshold(b, 0.5)};
  EXPECT_EQ(Fuse(FuseOp::kAnd, ops).cells, (std::vector<std::uint8_t>{1, 0, 0, 0}));
  EXPECT_EQ(Fuse(FuseOp::kOr, ops).cells, (std::vector<std::uint8_t>{1, 1, 1, 0}));
  EXPECT_EQ(Fuse(FuseOp::kAndNot, ops).cells, (std::vector<std::uint8_t>{0, 1, 0, 0}));
  EXPECT_EQ(Fuse(FuseOp::kXor, ops).cells, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  EXPECT_EQ(Threshold(a, 0.95).cells, (std::vector<std::uint8_t>{0, 0, 0, 0}));
}

TEST(FusionTest, RejectsSingleOperandAndMismatchedGrids) {
  GridGeometry g1, g2;
  g1.width_cells = g1.height_cells = 2;
  g2.width_cells = g2.height_cells = 3;
  EXPECT_THROW(Fuse(FuseOp::kOr, {MaskGrid(g1, 0)}), Error);
  EXPECT_THROW(Fuse(FuseOp::kOr, {MaskGrid(g1, 0), MaskGrid(g2, 0)}), Error);
}

TEST(RasterTest, CellCentresInsidePolygonAreSet) {
  const auto occ = testing::FreeGrid(10, 10, 1.0);
  MaskGrid mask(occ.geometry, 0);
  // A triangle with vertices on cell corners: cells whose centres lie inside or on its edge.
  const std::size_t n = RasterisePolygons({{{0.0, 0.0}, {4.0, 0.0}, {0.0, 4.0}}}, mask);
  std::size_t expected = 0;
  for (int iy = 0; iy < 10; ++iy) for (int ix = 0; ix < 10; ++ix) expected += (ix + 0.5) + (iy + 0.5) <= 4.0;
  EXPECT_EQ(n, expected);
  EXPECT_EQ(mask.at(0, 0), 1);
  EXPECT_EQ(mask.at(3, 0), 1);
  EXPECT_EQ(mask.at(3, 1), 0);
  // A polygon partly outside the grid is clipped, not an error.
  MaskGrid clipped(occ.geometry, 0);
  EXPECT_EQ(RasterisePolygons({{{8.0, 8.0}, {20.0, 8.0}, {20.0, 20.0}, {8.0, 20.0}}}, clipped), 4u);
}

}  // namespace
}  // namespace anchordb::engine
