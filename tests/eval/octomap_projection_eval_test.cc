// The height-band projection (engine/octomap/height_bands.h) of a tree built from rendered keyframes of the
// tabletop setting's room (sim/apartment.h), scored against the scene's known geometry cell by cell (issue 14,
// acceptance 2). It runs with the evaluations in ./build (-O2): its 3.6 million rays took minutes at the sanitizer
// build's -O0, and the sanitized projection and tree code is exercised by tests/engine/octomap_*_test.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "engine/octomap/height_bands.h"
#include "engine/octomap/occupancy_tree.h"
#include "engine/scene/projection.h"
#include "sim/apartment.h"
#include "sim/renderer.h"

namespace anchordb::engine {
namespace {

// Whether a point lies inside a primitive of the scene.
bool Solid(const sim::Scene& scene, const Eigen::Vector3d& p_W) {
  for (const sim::Primitive& prim : scene.primitives) {
    const Eigen::Vector3d p = prim.X_WorldPrim.inverse() * p_W;
    if (prim.shape == sim::Shape::kBox) {
      if ((p.cwiseAbs().array() <= (prim.size_m / 2).array()).all()) return true;
    } else if (p.head<2>().norm() <= prim.size_m.x() && std::abs(p.z()) <= prim.size_m.z() / 2) {
      return true;
    }
  }
  return false;
}

// A tree from `views` keyframes taken by a camera turning on the spot at the room's centre, 1.3 m up.
OccupancyTree RenderedRoomTree(const sim::Scene& scene, int views) {
  OccupancyTree tree;
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  for (int i = 0; i < views; ++i) {
    const double yaw = 2 * M_PI * i / views;
    const Eigen::Vector3d eye(0.2, -0.1, 1.3);
    const Eigen::Isometry3d X_WC = sim::LookAt(eye, eye + Eigen::Vector3d(2 * std::cos(yaw), 2 * std::sin(yaw), -1.0));
    const sim::Frame frame = sim::Render(scene, K, X_WC, sim::KindSensor(), 100 + i);
    const std::vector<Eigen::Vector3f> points = BackProjectRaw(frame.depth_mm, 1000.0, K, X_WC);
    tree.InsertCloud(points, eye, 6.0, i + 1);
  }
  return tree;
}

TEST(OctomapProjection, BaseBandOfARenderedRoomMatchesItsGeometry) {
  const sim::Scene scene = sim::MakeSetting(sim::Setting::kTA, 1).scene;
  const OccupancyTree tree = RenderedRoomTree(scene, 12);
  const TreeMetadata m = tree.Metadata();
  ASSERT_TRUE(m.min_map && m.max_map);
  // A grid reaching 1 m beyond everything the tree knows (as an imported base layer larger than the seen room).
  const GridGeometry g = GridCovering(*m.min_map - Eigen::Vector3d(1, 1, 0), *m.max_map + Eigen::Vector3d(1, 1, 0),
                                      tree.params().resolution_m);
  const HeightBand base{"base", 0.05, 0.3};  // above the floor's voxels, up to a robot base
  const Box3 box{{g.origin_x_m, g.origin_y_m, base.min_z_m},
                 {g.origin_x_m + g.width_cells * g.resolution_m, g.origin_y_m + g.height_cells * g.resolution_m,
                  base.max_z_m}};
  const float occupied_log_odds = 0.0f;  // probability 0.5
  const BandCells cells = ProjectBand(tree.KnownVoxels(box), occupied_log_odds, g, base);

  // Truth per cell: solid anywhere in the band over the cell's centre. Cells whose 3x3 neighbourhood mixes solid
  // and empty are the transition zone (a voxel straddles the surface) and are reported, not scored.
  auto truth = [&](int ix, int iy) {
    const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
    for (double z = base.min_z_m + 0.025; z < base.max_z_m; z += 0.05) {
      if (Solid(scene, {c.x(), c.y(), z})) return true;
    }
    return false;
  };
  std::vector<int> solid(g.CellCount());
  for (int iy = 0; iy < g.height_cells; ++iy)
    for (int ix = 0; ix < g.width_cells; ++ix) solid[iy * g.width_cells + ix] = truth(ix, iy);
  std::size_t right = 0, wrong = 0, unknown = 0, transition = 0, unknown_outside = 0, outside = 0;
  for (int iy = 0; iy < g.height_cells; ++iy) {
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const std::int8_t v = cells[iy * g.width_cells + ix];
      const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
      // Beyond the walls (and the niche behind the east wall, to x = 4.3 m) nothing can be seen.
      if (c.x() < -3.3 || c.x() > 4.4 || std::abs(c.y()) > 2.7) {
        ++outside;
        unknown_outside += v == -1;
        continue;
      }
      bool mixed = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (g.Contains(ix + dx, iy + dy) && solid[(iy + dy) * g.width_cells + ix + dx] != solid[iy * g.width_cells + ix])
            mixed = true;
      if (v == -1) { ++unknown; continue; }
      if (mixed) { ++transition; continue; }
      ((v == 100) == static_cast<bool>(solid[iy * g.width_cells + ix]) ? right : wrong) += 1;
    }
  }
  const double right_fraction = static_cast<double>(right) / static_cast<double>(right + wrong);
  std::printf("base band 0.05-0.3 m of the TA room, %d x %d cells at %.2f m: right %zu, wrong %zu (%.4f right), "
              "unknown %zu, transition %zu; beyond the walls %zu of %zu unknown\n",
              g.width_cells, g.height_cells, g.resolution_m, right, wrong, right_fraction, unknown, transition,
              unknown_outside, outside);
  EXPECT_GT(right + wrong, 10000u);  // most of the 6 x 5 m room is seen
  EXPECT_GE(right_fraction, 0.98);
  EXPECT_GT(outside, 1000u);
  EXPECT_EQ(unknown_outside, outside);  // unknown stays unknown
}

}  // namespace
}  // namespace anchordb::engine
