// Which surface region viewpoints go around (engine/grid/viewpoints.h ChooseSurfaceRegion) and the region's mask.
#include <gtest/gtest.h>

#include "engine/grid/regions.h"
#include "engine/grid/viewpoints.h"
#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace grid_viewpoint_surface_test {

// Two surfaces on a 20 m x 10 m grid (1 m cells): a large one at x 2..5 and a small one at x 14..15.
struct TwoSurfaces {
  ProbabilityGrid p{testing::FreeGrid(20, 10, 1.0).geometry, 0.0f};
  std::vector<Region> regions;
  TwoSurfaces() {
    for (int iy = 4; iy < 7; ++iy) {
      for (int ix = 2; ix < 6; ++ix) p.at(ix, iy) = 1.0f;
      for (int ix = 14; ix < 16; ++ix) p.at(ix, iy) = 1.0f;
    }
    regions = ExtractRegions(p, 0.5, 0.0);
  }
};

Agent Person(double x, double y, double heading_rad) {
  Agent a;
  a.id = "p";
  a.position_m = {x, y};
  a.heading_rad = heading_rad;
  return a;
}

TEST(GridViewpointSurface, TheRequestedRegionWins) {
  const TwoSurfaces s;
  ASSERT_EQ(s.regions.size(), 2u);
  EXPECT_EQ(ChooseSurfaceRegion(s.regions, s.p.geometry, Person(13.0, 5.5, 0.0), {}, 1), 1);
}

TEST(GridViewpointSurface, AnUnknownRegionIsNotFound) {
  const TwoSurfaces s;
  for (int id : {0, 3}) {
    try {
      ChooseSurfaceRegion(s.regions, s.p.geometry, Person(1.0, 1.0, 0.0), {}, id);
      FAIL() << "expected kNotFound for region " << id;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kNotFound);
      EXPECT_EQ(e.field(), "region");
    }
  }
}

TEST(GridViewpointSurface, OtherwiseTheAttendedRegion) {
  const TwoSurfaces s;
  // Next to the small surface (region 2) and facing it (+x).
  EXPECT_EQ(ChooseSurfaceRegion(s.regions, s.p.geometry, Person(13.5, 5.5, 0.0), {}, std::nullopt), 2);
}

TEST(GridViewpointSurface, OtherwiseTheNearestRegion) {
  const TwoSurfaces s;
  // Nearer the small surface but facing away from both.
  EXPECT_EQ(ChooseSurfaceRegion(s.regions, s.p.geometry, Person(12.5, 1.0, -1.5), {}, std::nullopt), 2);
  EXPECT_EQ(ChooseSurfaceRegion(s.regions, s.p.geometry, Person(7.0, 1.0, -1.5), {}, std::nullopt), 1);
}

TEST(GridViewpointSurface, NoRegionIsUnprocessable) {
  const TwoSurfaces s;
  EXPECT_THROW(ChooseSurfaceRegion({}, s.p.geometry, Person(1.0, 1.0, 0.0), {}, std::nullopt), Error);
}

TEST(GridViewpointSurface, RegionMaskMarksTheRegionsCells) {
  const TwoSurfaces s;
  const MaskGrid mask = RegionMask(s.regions[1], s.p.geometry);
  std::size_t set = 0;
  for (auto v : mask.cells) set += v;
  EXPECT_EQ(set, 6u);
  EXPECT_EQ(mask.at(14, 4), 1);
  EXPECT_EQ(mask.at(3, 4), 0);
}

}  // namespace
}  // namespace anchordb::engine
