// A ROS OccupancyGrid as a map_server pair (the rosbag importer's and the bridge node's conversion): read back with
// map_server's rules, every cell value lands where it was, as occupied, free or unknown.
#include "engine/grid/occupancy_grid_image.h"

#include <gtest/gtest.h>

#include "engine/grid/map_server.h"

namespace anchordb::engine {
namespace occupancy_grid_image_test {

TEST(OccupancyGridImageTest, MapServerReadsBackEveryCellValueAtItsPlace) {
  constexpr int kWidth = 17, kHeight = 6;  // 102 cells: every value -1 .. 100 once, row-major from the origin
  std::vector<std::int8_t> cells;
  for (int v = -1; v <= 100; ++v) cells.push_back(static_cast<std::int8_t>(v));
  GreyImage image{kWidth, kHeight, OccupancyGridImage(cells, kWidth, kHeight)};
  ASSERT_EQ(image.pixels.size(), cells.size());
  const ParsedYaml yaml = ParseMapServerYaml(OccupancyGridYaml("grid.png", 0.05, -3.25, 1.5, 0.25));
  EXPECT_TRUE(yaml.ignored_keys.empty());
  EXPECT_EQ(yaml.meta.image, "grid.png");
  EXPECT_DOUBLE_EQ(yaml.meta.resolution_m, 0.05);
  EXPECT_DOUBLE_EQ(yaml.meta.origin[0], -3.25);
  EXPECT_DOUBLE_EQ(yaml.meta.origin[1], 1.5);
  EXPECT_DOUBLE_EQ(yaml.meta.origin[2], 0.25);
  const OccupancyGrid read = ToOccupancy(image, yaml.meta);
  for (int iy = 0; iy < kHeight; ++iy) {
    for (int ix = 0; ix < kWidth; ++ix) {
      const int cell = cells[static_cast<std::size_t>(iy) * kWidth + ix];
      const int expected = cell >= 65 ? 100 : (cell >= 0 && cell <= 19) ? 0 : -1;
      EXPECT_EQ(read.at(ix, iy), expected) << "cell value " << cell;
    }
  }
}

TEST(OccupancyGridImageTest, CellsThatDoNotFillTheGridGiveNoImage) {
  EXPECT_TRUE(OccupancyGridImage(std::vector<std::int8_t>(5, 0), 2, 3).empty());
  EXPECT_TRUE(OccupancyGridImage({}, 0, 0).empty());
}

}  // namespace
}  // namespace anchordb::engine
