// Occupied voxels as leaf centres (engine/octomap/leaf_centres.h): a pruned block gives every leaf it stands for.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "engine/octomap/leaf_centres.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace octomap_leaf_centres_test {

Voxel Block(const Eigen::Vector3d& center_map, double size_m) {
  Voxel v;
  v.center_map = center_map;
  v.size_m = size_m;
  return v;
}

TEST(OctomapLeafCentresTest, ALeafIsItsCentreAndAPrunedBlockEveryLeafInIt) {
  const double res = 0.05;
  const auto one = LeafCentres({Block({1.0, 2.0, 0.5}, res)}, res, 100);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_TRUE(one[0].isApprox(Eigen::Vector3f(1.0f, 2.0f, 0.5f)));
  const Eigen::Vector3d c(1.0, 2.0, 0.6);
  const auto block = LeafCentres({Block(c, 4 * res)}, res, 100);  // 4 x 4 x 4 leaves
  ASSERT_EQ(block.size(), 64u);
  std::set<std::tuple<long, long, long>> cells;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3f& p : block) {
    const Eigen::Vector3d offset = p.cast<double>() - c;
    EXPECT_LE(offset.cwiseAbs().maxCoeff(), 1.5 * res + 1e-6) << "the outermost centres lie half a leaf inside";
    // Every centre at an odd multiple of half a leaf from the block's centre.
    const Eigen::Vector3d halves = offset / (0.5 * res);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::abs(std::fmod(halves[a], 2.0)), 1.0, 1e-3);
    cells.insert({std::lround(halves.x()), std::lround(halves.y()), std::lround(halves.z())});
    mean += p.cast<double>();
  }
  EXPECT_EQ(cells.size(), 64u) << "no leaf twice";
  EXPECT_TRUE((mean / 64.0).isApprox(c, 1e-6));
}

TEST(OctomapLeafCentresTest, MoreThanTheLimitIsRefusedUpToItIsServed) {
  const double res = 0.1;
  const std::vector<Voxel> voxels = {Block({0, 0, 0}, 2 * res), Block({1, 0, 0}, res)};  // 8 + 1 leaves
  EXPECT_EQ(LeafCentres(voxels, res, 9).size(), 9u);
  try {
    LeafCentres(voxels, res, 8);
    FAIL() << "9 leaves over a limit of 8";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kPayloadTooLarge);
  }
  EXPECT_TRUE(LeafCentres({}, res, 0).empty());
}

}  // namespace
}  // namespace anchordb::engine
