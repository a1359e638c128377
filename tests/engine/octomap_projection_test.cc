// The height-band projection (engine/octomap/height_bands.h) cell by cell. The projection of a whole rendered room
// scored against its geometry is an evaluation: tests/eval/octomap_projection_eval_test.cc.
#include "engine/octomap/height_bands.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/scene/projection.h"
#include "schema/error.h"
#include "sim/apartment.h"
#include "sim/renderer.h"

namespace anchordb::engine {
namespace octomap_projection_test {

TEST(OctomapProjection, UnknownStaysUnknownAndOccupiedWinsInACell) {
  GridGeometry g;
  g.width_cells = 4;
  g.height_cells = 2;
  g.resolution_m = 0.1;
  const std::vector<Voxel> voxels = {
      {{0.05, 0.05, 0.1}, 0.1, -2.0f, std::nullopt},  // free in cell (0, 0)
      {{0.15, 0.05, 0.1}, 0.1, -2.0f, std::nullopt},  // free and occupied in cell (1, 0)
      {{0.15, 0.05, 0.2}, 0.1, 2.0f, std::nullopt},
      {{0.35, 0.15, 0.9}, 0.1, 2.0f, std::nullopt},   // occupied, above the band
      {{0.2, 0.1, 0.1}, 0.2, -2.0f, std::nullopt},    // a pruned free leaf over cells (1..2, 0..1)
  };
  const BandCells cells = ProjectBand(voxels, 0.0f, g, {"base", 0.0, 0.3});
  EXPECT_EQ(cells, (BandCells{0, 100, 0, -1, -1, 0, 0, -1}));
  EXPECT_THROW(ProjectBand(voxels, 0.0f, g, {"bad", 0.3, 0.3}), Error);
  g.origin_yaw_rad = 0.1;
  EXPECT_THROW(ProjectBand(voxels, 0.0f, g, {"base", 0.0, 0.3}), Error);
}

}  // namespace
}  // namespace anchordb::engine
