// Real OctoMap files (../shared/data: octomap/geb079.bt, slambook2_rgbd/ch5_room_octomap_from_slambook1.bt) import,
// export and re-import identical leaf by leaf, through the engine and through the service's SQLite store; the ch5
// RGB-D views with their poses build a tree whose occupied voxels agree with slambook's tree built from them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include "engine/octomap/occupancy_tree.h"
#include "services/grid/grid_service.h"
#include "services/octomap/octomap_service.h"
#include "tests/support/real_data_files.h"
#include "tests/support/temp_dir.h"

namespace anchordb {
namespace {

std::string Data(const std::string& relative) { return testing::SharedDataPath(relative); }
using testing::ReadFile;

const char* kFiles[] = {"octomap/geb079.bt", "slambook2_rgbd/ch5_room_octomap_from_slambook1.bt"};

TEST(OctomapRealData, BtFilesImportExportAndReimportIdenticalLeafByLeaf) {
  for (const char* file : kFiles) {
    const std::string bytes = ReadFile(Data(file));
    engine::OccupancyTree once;
    once.ReadBt(bytes, 1);
    const engine::TreeMetadata m = once.Metadata();
    EXPECT_GT(m.occupied_leaves, 1000u) << file;
    engine::OccupancyTree twice;
    twice.ReadBt(once.WriteBt(), 1);
    EXPECT_TRUE(twice.SameLeaves(once)) << file;
    EXPECT_EQ(twice.WriteBt(), once.WriteBt()) << file;
    engine::OccupancyTree from_ot;
    from_ot.ReadOt(once.WriteOt(), 1);
    EXPECT_TRUE(from_ot.SameLeaves(once)) << file;
    std::printf("%s: res %.3f m, %zu nodes, %zu leaves (%zu occupied), %zu bytes in memory, .bt %zu B, .ot %zu B\n",
                file, once.params().resolution_m, m.nodes, m.leaves, m.occupied_leaves, m.memory_bytes, bytes.size(),
                once.WriteOt().size());
  }
  // geb079 is the 0.08 m corridor of octomap's test_io (532566 nodes).
  engine::OccupancyTree geb;
  geb.ReadBt(ReadFile(Data(kFiles[0])), 1);
  EXPECT_DOUBLE_EQ(geb.params().resolution_m, 0.08);
  EXPECT_EQ(geb.Metadata().nodes, 532566u);
}

TEST(OctomapRealData, TheStoreKeepsImportedTreesExactly) {
  testing::TempDir dir;
  storage::StoreOptions so;
  so.path = dir.File("octomap.sqlite");
  storage::Store store(so);
  services::GridService grid(store, {}, {});
  services::OctomapService octomap(store, {});
  for (const char* file : kFiles) {
    grid.CreateMap({"a", "a"});
    grid.CreateMap({"b", "b"});
    const std::string bytes = ReadFile(Data(file));
    octomap.Import("a", services::TreeFileFormat::kBt, bytes);
    const std::string bt = octomap.Export("a", services::TreeFileFormat::kBt).body;
    const std::string ot = octomap.Export("a", services::TreeFileFormat::kOt).body;
    octomap.Import("b", services::TreeFileFormat::kOt, ot);
    EXPECT_EQ(octomap.Export("b", services::TreeFileFormat::kOt).body, ot) << file;
    octomap.Import("b", services::TreeFileFormat::kBt, bt);
    EXPECT_EQ(octomap.Export("b", services::TreeFileFormat::kBt).body, bt) << file;
    engine::OccupancyTree direct;
    direct.ReadBt(bytes, 1);
    EXPECT_EQ(bt, direct.WriteBt()) << file;
    const services::OctomapInfo info = octomap.Get("a");
    std::printf("%s in SQLite: %lld bytes stored (zstd of .ot + stamps)\n", file, static_cast<long long>(info.stored_bytes));
    grid.DeleteMap("a");
    grid.DeleteMap("b");
  }
}

std::vector<std::uint16_t> ReadPgm16(const std::string& path) {
  int width = 0, height = 0;
  std::vector<std::uint16_t> px = testing::ReadPgm16(path, width, height);
  if (width != 640 || height != 480) throw std::runtime_error(path + " is not 640x480");
  return px;
}

// Occupied space as finest-resolution cells (pruned leaves expanded).
std::set<std::tuple<int, int, int>> OccupiedCells(const engine::OccupancyTree& tree) {
  const double r = tree.params().resolution_m;
  std::set<std::tuple<int, int, int>> cells;
  const engine::Box3 all{Eigen::Vector3d::Constant(-1e4), Eigen::Vector3d::Constant(1e4)};
  for (const engine::Voxel& v : tree.OccupiedVoxels(all, 1u << 30)) {
    const int n = static_cast<int>(std::lround(v.size_m / r));
    const Eigen::Vector3d lo = v.center_map - Eigen::Vector3d::Constant(v.size_m / 2 - r / 2);
    for (int i = 0; i < n; ++i) for (int j = 0; j < n; ++j) for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d c = lo + r * Eigen::Vector3d(i, j, k);
      cells.emplace(static_cast<int>(std::floor(c.x() / r)), static_cast<int>(std::floor(c.y() / r)),
                    static_cast<int>(std::floor(c.z() / r)));
    }
  }
  return cells;
}

TEST(OctomapRealData, Ch5ViewsBuildTheTreeSlambookBuilt) {
  // slambook ch13's recipe: skip d == 0 and d >= 7000 mm, back-project (fx 518, fy 519, cx 325.5, cy 253.5), move by
  // T_world_camera, insert with the camera centre as origin and no range limit.
  std::ifstream poses(Data("slambook2_rgbd/ch5/rgbd/pose.txt"));
  ASSERT_TRUE(poses);
  engine::OccupancyTree ours;
  for (int view = 1; view <= 5; ++view) {
    double t[3], q[4];
    poses >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3];
    const Eigen::Quaterniond R(q[3], q[0], q[1], q[2]);
    const Eigen::Vector3d p(t[0], t[1], t[2]);
    const std::vector<std::uint16_t> depth = ReadPgm16(Data("slambook2_rgbd/ch5/rgbd/depth/" + std::to_string(view) + ".pgm"));
    std::vector<Eigen::Vector3f> points;
    for (int v = 0; v < 480; ++v) {
      for (int u = 0; u < 640; ++u) {
        const std::uint16_t d = depth[v * 640 + u];
        if (d == 0 || d >= 7000) continue;
        const double z = d / 1000.0;
        const Eigen::Vector3d camera((u - 325.5) * z / 518.0, (v - 253.5) * z / 519.0, z);
        points.push_back((R.normalized() * camera + p).cast<float>());
      }
    }
    ours.InsertCloud(points, p, -1, view);
  }
  engine::OccupancyTree theirs;
  theirs.ReadBt(ReadFile(Data("slambook2_rgbd/ch5_room_octomap_from_slambook1.bt")), 1);
  const auto a = OccupiedCells(ours);
  const auto b = OccupiedCells(theirs);
  std::size_t common = 0;
  for (const auto& c : a) common += b.count(c);
  const double iou = static_cast<double>(common) / static_cast<double>(a.size() + b.size() - common);
  std::printf("ch5: ours %zu occupied cells, slambook %zu, common %zu, IoU %.4f\n", a.size(), b.size(), common, iou);
  EXPECT_GT(iou, 0.999);  // measured 1.0000 (44844 of 44846 cells)
}

}  // namespace
}  // namespace anchordb
