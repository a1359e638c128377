// Rules around observations and exports of grid layers: the sensor must stand on the grid (observation.h), and a
// probability image is described as a map_server map in scale mode (map_server.h).
#include <gtest/gtest.h>

#include "engine/grid/map_server.h"
#include "engine/grid/observation.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace grid_layer_export_test {

TEST(GridLayerExport, SensorInsideGridUsesTheCellsOfTheGrid) {
  GridGeometry g = testing::FreeGrid(4, 2, 0.5).geometry;  // 2 m x 1 m
  g.origin_x_m = -1.0;
  Observation o;
  o.sensor_position_m = {-1.0, 0.0};  // the lower-left corner belongs to cell (0, 0)
  EXPECT_TRUE(SensorInsideGrid(g, o));
  o.sensor_position_m = {0.99, 0.99};
  EXPECT_TRUE(SensorInsideGrid(g, o));
  o.sensor_position_m = {1.0, 0.5};  // the right edge does not
  EXPECT_FALSE(SensorInsideGrid(g, o));
  o.sensor_position_m = {-1.01, 0.5};
  EXPECT_FALSE(SensorInsideGrid(g, o));
}

TEST(GridLayerExport, ScaleModeMetaCarriesTheGridGeometry) {
  GridGeometry g;
  g.width_cells = 3;
  g.height_cells = 2;
  g.resolution_m = 0.1;
  g.origin_x_m = -2.0;
  g.origin_y_m = 1.5;
  g.origin_yaw_rad = 0.25;
  const MapServerMeta m = ScaleModeMeta(g, "surface.pgm");
  EXPECT_EQ(m.image, "surface.pgm");
  EXPECT_EQ(m.resolution_m, 0.1);
  EXPECT_EQ(m.origin[0], -2.0);
  EXPECT_EQ(m.origin[1], 1.5);
  EXPECT_EQ(m.origin[2], 0.25);
  EXPECT_EQ(m.mode, MapMode::kScale);
  EXPECT_TRUE(m.mode_given);
  EXPECT_EQ(m.negate, MapServerMeta{}.negate);
  EXPECT_EQ(m.occupied_thresh, MapServerMeta{}.occupied_thresh);
  EXPECT_EQ(m.free_thresh, MapServerMeta{}.free_thresh);
}

}  // namespace
}  // namespace anchordb::engine
