// The occupancy tree (engine/octomap): ray-cast insertion, queries, edits, .ot/.bt round trips and bad input.
#include "engine/octomap/occupancy_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "schema/error.h"

namespace anchordb::engine {
namespace octomap_tree_test {

// A wall at x = 2 m facing the origin: a 1 m x 1 m square of points, 1 cm apart.
std::vector<Eigen::Vector3f> Wall(float x_m = 2.0f) {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i <= 100; ++i) {
    for (int j = 0; j <= 100; ++j) points.emplace_back(x_m, -0.5f + 0.01f * i, 0.5f + 0.01f * j);
  }
  return points;
}

OccupancyTree WallTree(std::int64_t stamp_ns = 1000) {
  OccupancyTree tree;
  tree.InsertCloud(Wall(), Eigen::Vector3d(0, 0, 1), 5.0, stamp_ns);
  return tree;
}

TEST(OctomapTree, RayCastInsertionMarksFreeSpaceAndTheWall) {
  const OccupancyTree tree = WallTree();
  const auto q = tree.Query({{1.0, 0.0, 1.0}, {2.01, 0.0, 1.0}, {3.0, 0.0, 1.0}, {1.0, 0.0, 3.0}});
  EXPECT_EQ(q[0].state, VoxelState::kFree);
  EXPECT_LT(q[0].probability, 0.5);
  EXPECT_EQ(q[1].state, VoxelState::kOccupied);
  EXPECT_NEAR(q[1].probability, 0.7, 1e-3);  // one hit from the prior
  EXPECT_EQ(q[1].stamp_ns, 1000);
  EXPECT_EQ(q[2].state, VoxelState::kUnknown);  // behind the wall
  EXPECT_EQ(q[3].state, VoxelState::kUnknown);  // never seen
  EXPECT_DOUBLE_EQ(q[3].probability, 0.5);
}

TEST(OctomapTree, MaxRangeCutsRaysWithoutMarkingTheirEnds) {
  OccupancyTree tree;
  tree.InsertCloud(Wall(), Eigen::Vector3d(0, 0, 1), 1.5, 1);
  const auto q = tree.Query({{1.0, 0.0, 1.0}, {2.01, 0.0, 1.0}});
  EXPECT_EQ(q[0].state, VoxelState::kFree);
  EXPECT_EQ(q[1].state, VoxelState::kUnknown);
}

TEST(OctomapTree, RayCastFindsTheFirstOccupiedVoxel) {
  const OccupancyTree tree = WallTree();
  const RayHit hit = tree.CastRay({0, 0, 1}, {1, 0, 0}, 10.0, false);
  EXPECT_EQ(hit.stopped_by, VoxelState::kOccupied);
  EXPECT_NEAR(hit.end_map.x(), 2.0, 0.05);
  const RayHit up = tree.CastRay({0, 0, 1}, {0, 0, 1}, 10.0, false);
  EXPECT_EQ(up.stopped_by, VoxelState::kUnknown);
  EXPECT_THROW(tree.CastRay({0, 0, 1}, {0, 0, 0}, 10.0, false), Error);
}

TEST(OctomapTree, OccupiedVoxelsInABoxAreTheWallsOnly) {
  const OccupancyTree tree = WallTree();
  bool truncated = true;
  const auto voxels = tree.OccupiedVoxels({{1.5, -1, 0}, {2.5, 1, 2}}, 100000, &truncated);
  EXPECT_FALSE(truncated);
  ASSERT_GT(voxels.size(), 300u);  // 1 m^2 at 5 cm: about 400 voxels
  for (const Voxel& v : voxels) EXPECT_NEAR(v.center_map.x(), 2.0, 0.05);
  EXPECT_TRUE(tree.OccupiedVoxels({{0, -1, 0}, {1.5, 1, 2}}, 100000).empty());
  tree.OccupiedVoxels({{1.5, -1, 0}, {2.5, 1, 2}}, 10, &truncated);
  EXPECT_TRUE(truncated);
}

TEST(OctomapTree, OtRoundTripKeepsLogOddsLeafByLeaf) {
  OccupancyTree tree = WallTree();
  tree.InsertCloud(Wall(), Eigen::Vector3d(0, 0, 1), 5.0, 2000);  // two hits: not at a clamping bound
  const std::string ot = tree.WriteOt();
  OccupancyTree back;
  back.ReadOt(ot, 5);
  EXPECT_TRUE(back.SameLeaves(tree));
  EXPECT_EQ(back.WriteOt(), ot);
  const auto q = back.Query({{2.01, 0.0, 1.0}});
  EXPECT_NEAR(q[0].probability, 1 / (1 + std::pow(0.3 / 0.7, 2)), 1e-3);
  EXPECT_EQ(q[0].stamp_ns, 5);  // an import's stamp
}

TEST(OctomapTree, BtRoundTripIsStableAfterTheFirstImport) {
  const OccupancyTree tree = WallTree();
  OccupancyTree once;
  once.ReadBt(tree.WriteBt(), 1);
  OccupancyTree twice;
  twice.ReadBt(once.WriteBt(), 1);
  EXPECT_TRUE(twice.SameLeaves(once));
  EXPECT_EQ(once.Metadata().occupied_leaves, tree.Metadata().occupied_leaves);
}

TEST(OctomapTree, BadFilesLeaveTheTreeUnchanged) {
  OccupancyTree tree = WallTree();
  const OccupancyTree before = tree.Clone();
  const std::string ot = tree.WriteOt();
  const std::string bt = tree.WriteBt();
  EXPECT_THROW(tree.ReadOt("# not an octomap\n", 1), Error);
  EXPECT_THROW(tree.ReadOt(ot.substr(0, ot.size() / 2), 1), Error);
  EXPECT_THROW(tree.ReadBt(bt.substr(0, bt.size() - 7), 1), Error);
  EXPECT_THROW(tree.ReadBt(ot, 1), Error);  // an .ot where a .bt is expected
  EXPECT_THROW(tree.ReadOt(bt, 1), Error);
  EXPECT_TRUE(tree.SameLeaves(before));
}

// liboctomap keeps reading a cut-off node stream on bytes it never read (found as a stack overflow in the sanitized
// server): every cut of a whole body, at any byte, must be refused before it gets there, and so must a forged stream
// whose nodes claim children far below the tree's 16 levels.
TEST(OctomapTree, EveryCutOfABodyAndAForgedDeepStreamAreRefused) {
  OccupancyTree tree = WallTree();
  const OccupancyTree before = tree.Clone();
  const std::string ot = tree.WriteOt();
  const std::string bt = tree.WriteBt();
  const std::size_t ot_data = ot.find("\ndata\n") + 6;
  const std::size_t bt_data = bt.find("\ndata\n") + 6;
  ASSERT_GT(ot.size(), ot_data + 1000);
  ASSERT_GT(bt.size(), bt_data + 100);
  // Every cut in the first 600 node bytes and the last 600, and every 97th in between.
  const auto cuts = [](std::size_t data, std::size_t size) {
    std::vector<std::size_t> out;
    for (std::size_t cut = data; cut < size; cut += (cut < data + 600 || cut + 600 > size) ? 1 : 97) out.push_back(cut);
    return out;
  };
  const auto refused = [&](const std::string& body, std::size_t data, bool is_ot) {
    int n = 0;
    for (const std::size_t cut : cuts(data, body.size())) {
      try {
        is_ot ? tree.ReadOt(body.substr(0, cut), 1) : tree.ReadBt(body.substr(0, cut), 1);
      } catch (const Error& e) {
        n += e.code() == ErrorCode::kInvalidArgument ? 1 : 0;
      }
    }
    return n;
  };
  EXPECT_EQ(refused(ot, ot_data, true), static_cast<int>(cuts(ot_data, ot.size()).size()));
  EXPECT_EQ(refused(bt, bt_data, false), static_cast<int>(cuts(bt_data, bt.size()).size()));
  // 64 nested nodes, each with its first child only: well past depth 16, and long enough to be read whole.
  std::string deep_ot = ot.substr(0, ot_data), deep_bt = bt.substr(0, bt_data);
  for (int d = 0; d < 64; ++d) {
    deep_ot += std::string(4, '\0') + std::string(1, '\x01');
    deep_bt += std::string(1, '\x03') + std::string(1, '\0');
  }
  deep_ot += std::string(5, '\0');
  deep_bt += std::string(2, '\0');
  EXPECT_THROW(tree.ReadOt(deep_ot, 1), Error);
  EXPECT_THROW(tree.ReadBt(deep_bt, 1), Error);
  // The nodes start where liboctomap's header reader says, not at a later `data` line: "res 0.1data" ends the header
  // for liboctomap (it reads the number, then the keyword), so the forged chain after it is what would be read.
  const std::string chain_ot = deep_ot.substr(ot_data), chain_bt = deep_bt.substr(bt_data);
  const std::string hidden = "id OcTree\nsize 64\nres 0.1data\n";
  EXPECT_THROW(tree.ReadOt("# Octomap OcTree file\n" + hidden + chain_ot + "\ndata\n" + std::string(5, '\0'), 1), Error);
  EXPECT_THROW(tree.ReadBt("# Octomap OcTree binary file\n" + hidden + chain_bt + "\ndata\n" + std::string(2, '\0'), 1),
               Error);
  // Another tree type has other node records: refused before liboctomap reads them.
  std::string colour = ot;
  colour.replace(colour.find("id OcTree"), 9, "id ColorOcTree");
  EXPECT_THROW(tree.ReadOt(colour, 1), Error);
  EXPECT_TRUE(tree.SameLeaves(before));
  // An empty tree's .bt has no node bytes (size 0) and reads back.
  OccupancyTree empty;
  OccupancyTree empty_back;
  EXPECT_NO_THROW(empty_back.ReadBt(empty.WriteBt(), 1));
  EXPECT_TRUE(empty_back.SameLeaves(empty));
  // The whole bodies still read.
  OccupancyTree back;
  back.ReadOt(ot, 1);
  EXPECT_TRUE(back.SameLeaves(before));
}

TEST(OctomapTree, BadCloudsLeaveTheTreeUnchanged) {
  OccupancyTree tree = WallTree();
  const OccupancyTree before = tree.Clone();
  std::vector<Eigen::Vector3f> nan_points = Wall(1.0f);
  nan_points[77].y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(tree.InsertCloud(nan_points, {0, 0, 1}, 5.0, 9), Error);
  EXPECT_THROW(tree.InsertCloud({{1e6f, 0, 0}}, {0, 0, 1}, 5.0, 9), Error);
  EXPECT_THROW(tree.InsertCloud(Wall(1.0f), {2.01, 0.0, 1.0}, 5.0, 9), Error);  // origin inside the wall
  EXPECT_THROW(tree.InsertCloud(Wall(1.0f), {0, std::numeric_limits<double>::infinity(), 1}, 5.0, 9), Error);
  EXPECT_TRUE(tree.SameLeaves(before));
}

TEST(OctomapTree, AbsurdParametersAreRejected) {
  for (double resolution : {0.0, -0.05, 1e-6, 100.0, std::numeric_limits<double>::quiet_NaN()}) {
    OccupancyTreeParams p;
    p.resolution_m = resolution;
    EXPECT_THROW(OccupancyTree{p}, Error) << resolution;
  }
  OccupancyTreeParams p;
  p.prob_hit = 0.4;
  EXPECT_THROW(ValidateOccupancyTreeParams(p), Error);
  OccupancyTree tree;
  p = tree.params();
  p.resolution_m = 0.1;
  EXPECT_THROW(tree.SetParams(p), Error);
}

TEST(OctomapTree, ClearBoxFreesKnownVoxelsAndLeavesUnknownUnknown) {
  OccupancyTree tree = WallTree();
  const std::size_t changed = tree.ClearBox({{1.9, -0.2, 0.8}, {2.1, 0.2, 1.2}}, 3000);
  EXPECT_GT(changed, 0u);
  const auto q = tree.Query({{2.01, 0.0, 1.0}, {2.01, 0.45, 1.0}, {2.5, 0.0, 1.0}});
  EXPECT_EQ(q[0].state, VoxelState::kFree);
  EXPECT_EQ(q[0].stamp_ns, 3000);
  EXPECT_EQ(q[1].state, VoxelState::kOccupied);  // outside the box
  EXPECT_EQ(q[2].state, VoxelState::kUnknown);   // unknown inside the box stays unknown
  EXPECT_EQ(tree.ClearBox({{1.9, -0.2, 0.8}, {2.1, 0.2, 1.2}}, 3001), 0u);
}

TEST(OctomapTree, ForgettingRemovesVoxelsNotConfirmedSinceTheCutoff) {
  OccupancyTree tree;
  tree.InsertCloud(Wall(2.0f), {0, 0, 1}, 5.0, 100);
  tree.InsertCloud({{0.0f, 3.0f, 1.0f}}, {0, 0, 1}, 5.0, 500);  // a later ray to the side
  const std::size_t removed = tree.ForgetOlderThan(300);
  EXPECT_GT(removed, 0u);
  const auto q = tree.Query({{2.01, 0.0, 1.0}, {0.0, 3.0, 1.0}, {0.0, 1.5, 1.0}});
  EXPECT_EQ(q[0].state, VoxelState::kUnknown);
  EXPECT_EQ(q[1].state, VoxelState::kOccupied);
  EXPECT_EQ(q[2].state, VoxelState::kFree);
  EXPECT_EQ(q[2].stamp_ns, 500);
}

TEST(OctomapTree, StampsRestoreBesideTheOtStream) {
  const OccupancyTree tree = WallTree(777);
  OccupancyTree back;
  back.ReadOt(tree.WriteOt(), 0);
  back.RestoreStamps(tree.Stamps());
  EXPECT_EQ(back.Stamps(), tree.Stamps());
  EXPECT_EQ(back.Query({{1.0, 0.0, 1.0}})[0].stamp_ns, 777);
  const TreeMetadata m = back.Metadata();
  EXPECT_GT(m.leaves, m.occupied_leaves);
  ASSERT_TRUE(m.min_map && m.max_map);
  EXPECT_NEAR(m.max_map->x(), 2.05, 0.06);
}

}  // namespace
}  // namespace anchordb::engine
