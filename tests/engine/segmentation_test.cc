// Segmentation of furniture (thesis 5.3.1): bounding planes removed, pieces found as clusters, flying parts merged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "engine/scene/projection.h"
#include "engine/segmentation/footprint.h"
#include "engine/segmentation/furniture_segmentation.h"
#include "engine/segmentation/geometric_categories.h"
#include "schema/error.h"
#include "sim/apartment.h"
#include "sim/apartment_furnished.h"
#include "sim/renderer.h"

namespace anchordb::engine::segmentation {
namespace segmentation_test {

std::vector<Eigen::Vector3f> RoomCloud(const sim::FurnishedRoom& room, std::uint64_t seed, double max_depth_m = 3.5) {
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  std::vector<Eigen::Vector3f> cloud;
  for (std::size_t v = 0; v < room.X_WorldCamera.size(); ++v) {
    sim::Frame f = sim::Render(room.scene, K, room.X_WorldCamera[v], sim::SensorModel{}, seed * 31 + v);
    for (auto& d : f.depth_mm) {
      if (d > max_depth_m * 1000.0) d = 0;
    }
    const auto points = BackProjectRaw(f.depth_mm, 1000.0, K, room.X_WorldCamera[v]);
    cloud.insert(cloud.end(), points.begin(), points.end());
  }
  return cloud;
}

Footprint TrueFootprint(const sim::PlacedPiece& p) {
  Footprint f;
  f.centre_m = p.centre_m;
  f.extent_m = p.extent_m;
  f.yaw_rad = p.yaw_rad;
  f.max_z_m = p.height_m;
  return f;
}

TEST(FootprintTest, PrincipalAxesAndIoU) {
  std::vector<Eigen::Vector3f> points;
  const double yaw = 23.0 * std::numbers::pi / 180.0;  // a heading of the 1 deg sweep
  for (int i = 0; i <= 40; ++i) {
    for (int k = 0; k <= 10; ++k) {
      const Eigen::Vector2d local(-1.0 + 0.05 * i, -0.25 + 0.05 * k);
      const Eigen::Vector2d w = Eigen::Rotation2Dd(yaw) * local + Eigen::Vector2d(2.0, -1.0);
      points.emplace_back(static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(0.1 * (k % 3)));
    }
  }
  const Footprint f = FootprintOf(points, 0.0);
  EXPECT_NEAR(f.yaw_rad, yaw, 1e-3);
  EXPECT_NEAR(f.extent_m.x(), 2.0, 1e-3);
  EXPECT_NEAR(f.extent_m.y(), 0.5, 1e-3);
  EXPECT_NEAR(f.centre_m.x(), 2.0, 1e-3);
  EXPECT_NEAR(f.height_m(), 0.2, 1e-6);
  EXPECT_NEAR(FootprintIoU(f, f), 1.0, 1e-4);
  Footprint half = f;
  half.centre_m += Eigen::Vector2d(std::cos(yaw), std::sin(yaw)) * 1.0;  // shifted by half its length
  EXPECT_NEAR(FootprintIoU(f, half), 1.0 / 3.0, 1e-3);
  Footprint far = f;
  far.centre_m += Eigen::Vector2d(10, 0);
  EXPECT_EQ(FootprintIoU(f, far), 0.0);
  Footprint flat = f;
  flat.extent_m.y() = 0.0;
  EXPECT_EQ(FootprintIoU(f, flat), 0.0);
}

TEST(SegmentationTest, FindsEveryPieceOfTheFurnishedRoomAndNothingElse) {
  const sim::FurnishedRoom room = sim::MakeFurnishedRoom(3);
  const SegmentationResult r = SegmentFurniture(RoomCloud(room, 3));
  int floors = 0, walls = 0;
  for (const FittedPlane& p : r.planes) {
    floors += p.role == PlaneRole::kFloor;
    walls += p.role == PlaneRole::kWall || p.role == PlaneRole::kWallWithOpening;
  }
  EXPECT_EQ(floors, 1);
  EXPECT_GE(walls, 3);
  ASSERT_TRUE(r.floor_z_m);
  EXPECT_NEAR(*r.floor_z_m, 0.0, 0.03);
  std::vector<bool> found(room.pieces.size(), false);
  int right = 0;
  for (const FurnitureSegment& s : r.segments) {
    EXPECT_TRUE(s.touches_floor || s.touches_wall);
    bool hit = false;
    for (std::size_t i = 0; i < room.pieces.size(); ++i) {
      if (FootprintIoU(s.footprint, TrueFootprint(room.pieces[i])) >= 0.5) hit = true, found[i] = true;
    }
    right += hit;
    if (!hit) ADD_FAILURE() << "segment at " << s.footprint.centre_m.transpose() << " extent " << s.footprint.extent_m.transpose()
                            << " yaw " << s.footprint.yaw_rad << " z " << s.footprint.min_z_m << ".." << s.footprint.max_z_m
                            << " points " << s.points_m.size();
    if (!hit && std::getenv("SEG_DUMP")) {
      FILE* out = std::fopen(("/tmp/seg_" + std::to_string(s.points_m.size()) + ".xyz").c_str(), "w");
      for (const auto& q : s.points_m) std::fprintf(out, "%f %f %f\n", q.x(), q.y(), q.z());
      std::fclose(out);
    }
  }
  for (std::size_t i = 0; i < room.pieces.size(); ++i) {
    if (found[i]) continue;
    double best = 0;
    for (const FurnitureSegment& s : r.segments) best = std::max(best, FootprintIoU(s.footprint, TrueFootprint(room.pieces[i])));
    ADD_FAILURE() << room.pieces[i].category << " not found (best IoU " << best << ")";
  }
  int recalled = 0;
  for (bool f : found) recalled += f;
  EXPECT_EQ(recalled, static_cast<int>(room.pieces.size()));
  EXPECT_EQ(right, static_cast<int>(r.segments.size()));
}

TEST(SegmentationTest, FlyingClusterMergesIntoTheClusterBelow) {
  // A floor, a wall, a cabinet on the floor and a slab floating 0.15 m above it (its link hidden by occlusion).
  std::vector<Eigen::Vector3f> cloud;
  const float step = 0.02f;
  for (float x = -2.0f; x <= 2.0f; x += step) {
    for (float y = -2.0f; y <= 2.0f; y += step) cloud.emplace_back(x, y, 0.0f);
  }
  for (float y = -2.0f; y <= 2.0f; y += step) {
    for (float z = 0.0f; z <= 2.0f; z += step) cloud.emplace_back(2.0f, y, z);
  }
  const auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi) {
    for (float x = lo.x(); x <= hi.x(); x += step) {
      for (float y = lo.y(); y <= hi.y(); y += step) {
        cloud.emplace_back(x, y, hi.z());
        cloud.emplace_back(x, y, lo.z());
      }
    }
    for (float x = lo.x(); x <= hi.x(); x += step) {
      for (float z = lo.z(); z <= hi.z(); z += step) cloud.emplace_back(x, lo.y(), z), cloud.emplace_back(x, hi.y(), z);
    }
    for (float y = lo.y(); y <= hi.y(); y += step) {
      for (float z = lo.z(); z <= hi.z(); z += step) cloud.emplace_back(lo.x(), y, z), cloud.emplace_back(hi.x(), y, z);
    }
  };
  box({-1.0f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.6f});      // cabinet on the floor
  box({-0.9f, -0.4f, 0.75f}, {-0.1f, 0.4f, 0.95f});   // flying part above it
  box({-1.5f, 1.2f, 1.2f}, {-1.0f, 1.6f, 1.4f});       // flying with nothing below: dropped
  const SegmentationResult r = SegmentFurniture(cloud);
  ASSERT_EQ(r.segments.size(), 1u);
  EXPECT_EQ(r.segments[0].merged_flying, 1);
  EXPECT_EQ(r.flying_dropped, 1);
  EXPECT_NEAR(r.segments[0].footprint.max_z_m, 0.95, 0.03);
  EXPECT_TRUE(r.segments[0].touches_floor);
}

TEST(SegmentationTest, BridgeOfFlyingPixelsIsCutBetweenTwoPieces) {
  // A floor, a wall and two cabinets 0.4 m apart, joined by three thin trails of flying pixels (one point per
  // voxel, the mixed depths a Kinect reports across the gap): one Euclidean cluster, two pieces.
  std::vector<Eigen::Vector3f> cloud;
  const float step = 0.02f;
  for (float x = -2.0f; x <= 2.0f; x += step) {
    for (float y = -2.0f; y <= 2.0f; y += step) cloud.emplace_back(x, y, 0.0f);
  }
  for (float y = -2.0f; y <= 2.0f; y += step) {
    for (float z = 0.0f; z <= 2.0f; z += step) cloud.emplace_back(2.0f, y, z);
  }
  const auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi) {
    for (float x = lo.x(); x <= hi.x(); x += step) {
      for (float y = lo.y(); y <= hi.y(); y += step) cloud.emplace_back(x, y, hi.z());
      for (float z = lo.z(); z <= hi.z(); z += step) cloud.emplace_back(x, lo.y(), z), cloud.emplace_back(x, hi.y(), z);
    }
    for (float y = lo.y(); y <= hi.y(); y += step) {
      for (float z = lo.z(); z <= hi.z(); z += step) cloud.emplace_back(lo.x(), y, z), cloud.emplace_back(hi.x(), y, z);
    }
  };
  box({-1.0f, -0.5f, 0.0f}, {-0.4f, 0.5f, 0.7f});
  box({0.0f, -0.5f, 0.0f}, {0.6f, 0.5f, 0.7f});
  for (const float y : {-0.29f, 0.01f, 0.31f}) {
    for (float x = -0.39f; x < 0.0f; x += step) cloud.emplace_back(x, y, 0.35f);
  }
  SegmentationParams no_split;
  no_split.core_density = 0.0;
  const SegmentationResult joined = SegmentFurniture(cloud, no_split);
  ASSERT_EQ(joined.segments.size(), 1u);  // without the cut the trails hold the two cabinets together
  const SegmentationResult r = SegmentFurniture(cloud);
  EXPECT_EQ(r.bridges_cut, 1);
  ASSERT_EQ(r.segments.size(), 2u);
  std::vector<double> centres = {r.segments[0].footprint.centre_m.x(), r.segments[1].footprint.centre_m.x()};
  std::sort(centres.begin(), centres.end());
  EXPECT_NEAR(centres[0], -0.7, 0.12);
  EXPECT_NEAR(centres[1], 0.3, 0.12);
  for (const FurnitureSegment& s : r.segments) {
    EXPECT_TRUE(s.touches_floor);
    EXPECT_NEAR(s.footprint.max_z_m, 0.7, 0.03);
  }
  // Footprints each ~0.6 x 1.0 m with at most half of the 0.4 m trail: each matches its cabinet.
  Footprint a, b;
  a.centre_m = Eigen::Vector2d(-0.7, 0.0), b.centre_m = Eigen::Vector2d(0.3, 0.0);
  a.extent_m = b.extent_m = Eigen::Vector2d(1.0, 0.6);
  a.yaw_rad = b.yaw_rad = std::numbers::pi / 2;
  for (const FurnitureSegment& s : r.segments) EXPECT_GE(std::max(FootprintIoU(s.footprint, a), FootprintIoU(s.footprint, b)), 0.6);
}

TEST(SegmentationTest, WallWithAnOpeningIsRemovedByItsSize) {
  // A wall at x = 2 with a door; through the door another room's furniture stands behind it.
  std::vector<Eigen::Vector3f> cloud;
  const float step = 0.02f;
  for (float x = -2.0f; x <= 4.0f; x += step) {
    for (float y = -2.0f; y <= 2.0f; y += step) cloud.emplace_back(x, y, 0.0f);
  }
  for (float y = -2.0f; y <= 2.0f; y += step) {
    for (float z = 0.0f; z <= 2.4f; z += step) {
      if (!(y > -0.5f && y < 0.4f && z < 2.0f)) cloud.emplace_back(2.0f, y, z);
    }
  }
  for (float y = -0.3f; y <= 0.3f; y += step) {  // the piece in the next room, seen through the door
    for (float z = 0.0f; z <= 0.8f; z += step) cloud.emplace_back(3.0f, y, z);
  }
  const SegmentationResult r = SegmentFurniture(cloud);
  bool opening = false;
  for (const FittedPlane& p : r.planes) opening |= p.role == PlaneRole::kWallWithOpening;
  EXPECT_TRUE(opening);
  ASSERT_EQ(r.segments.size(), 1u);  // the piece behind the door, not the wall
  EXPECT_NEAR(r.segments[0].footprint.centre_m.x(), 3.0, 0.05);
}

TEST(SegmentationTest, EmptyAndNonFiniteCloudsAndBadParameters) {
  EXPECT_TRUE(SegmentFurniture({}).segments.empty());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const SegmentationResult r = SegmentFurniture({Eigen::Vector3f(nan, 0, 0), Eigen::Vector3f(1, 2, 3)});
  EXPECT_EQ(r.input_points, 1u);
  EXPECT_TRUE(r.segments.empty());
  SegmentationParams bad;
  bad.voxel_m = 0.0;
  try {
    SegmentFurniture({Eigen::Vector3f(1, 2, 3)}, bad);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(e.field(), "params.voxel_m");
  }
}

TEST(GeometricCategoriesTest, TablesAndShelvesByTheirShape) {
  const std::vector<std::string> ids = {"table", "shelf", "sofa", "chair", "unknown"};
  const auto p_dining = GeometricCategories({0.75, 1.4, 0.8, 0.6, 0.97}, ids);
  EXPECT_GT(p_dining[0], 0.5);
  const auto p_shelf = GeometricCategories({1.8, 1.0, 0.35, 0.1, 0.5}, ids);
  EXPECT_GT(p_shelf[1], 0.5);
  double sum = 0;
  for (double v : p_shelf) sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-9);
  const auto none = GeometricCategories({1, 1, 1, 1, 1}, {"x", "y"});
  EXPECT_DOUBLE_EQ(none[0], 0.5);
  // A sofa and a table of the same size: the sofa's densest layer is its seat, half way up.
  const auto p_sofa = GeometricCategories({0.85, 1.8, 0.9, 0.35, 0.52}, ids);
  EXPECT_GT(p_sofa[2], p_sofa[0]);
  const auto p_table = GeometricCategories({0.85, 1.8, 0.9, 0.35, 0.97}, ids);
  EXPECT_GT(p_table[0], p_table[2]);
}

}  // namespace
}  // namespace anchordb::engine::segmentation
