#include "sim/apartment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

namespace anchordb::sim {
namespace {

std::map<int, int> PixelsPerId(const Frame& f) {
  std::map<int, int> counts;
  for (const std::int32_t id : f.object_id) ++counts[id];
  return counts;
}

double HeadingRad(const Eigen::Isometry3d& X_WorldCamera) {
  const Eigen::Vector3d axis = X_WorldCamera.linear().col(2);
  return std::atan2(axis.y(), axis.x());
}

// Pixel of a world point, or nullopt if behind the camera.
std::optional<Eigen::Vector2d> Project(const PinholeIntrinsics& K, const Eigen::Isometry3d& X_WorldCamera,
                                       const Eigen::Vector3d& p_World) {
  const Eigen::Vector3d p_C = X_WorldCamera.inverse() * p_World;
  if (p_C.z() <= 0.0) return std::nullopt;
  return Eigen::Vector2d(K.fx * p_C.x() / p_C.z() + K.cx, K.fy * p_C.y() / p_C.z() + K.cy);
}

class SettingTest : public testing::TestWithParam<Setting> {};

TEST_P(SettingTest, BuildsAndRendersWithTheMovableObjectsVisibleFromBothViewpoints) {
  const PinholeIntrinsics K = KinectIntrinsics();
  for (const std::uint64_t seed : {1u, 2u}) {
    const SettingScene s = MakeSetting(GetParam(), seed);
    ASSERT_GE(s.movable_ids.size(), 3u);
    std::set<int> object_ids;
    for (const Object& o : s.scene.objects) {
      EXPECT_TRUE(object_ids.insert(o.id).second) << "duplicate object id " << o.id;
      EXPECT_TRUE(o.kind == "static" || o.kind == "movable" || o.kind == "person") << o.kind;
    }
    for (const Primitive& p : s.scene.primitives) EXPECT_TRUE(object_ids.count(p.object_id)) << p.object_id;
    std::set<int> special(s.movable_ids.begin(), s.movable_ids.end());
    special.insert(s.thin_object_id);
    special.insert(s.tall_object_id);
    EXPECT_EQ(special.size(), s.movable_ids.size() + 2) << "movable, thin and tall ids must differ";
    for (const int id : special) EXPECT_TRUE(object_ids.count(id)) << id;

    const Frame a = Render(s.scene, K, s.X_WorldCameraA, SensorModel{}, seed);
    const Frame b = Render(s.scene, K, s.X_WorldCameraB, SensorModel{}, seed);
    std::map<int, int> in_a = PixelsPerId(a), in_b = PixelsPerId(b);
    for (const int id : s.movable_ids) {
      EXPECT_GE(in_a[id], 200) << SettingName(GetParam()) << " seed " << seed << " object " << id << " from A";
      EXPECT_GE(in_b[id], 100) << SettingName(GetParam()) << " seed " << seed << " object " << id << " from B";
    }
    for (const int id : {s.thin_object_id, s.tall_object_id}) {
      EXPECT_GE(in_a[id], 200) << SettingName(GetParam()) << " object " << id << " from A";
      EXPECT_GE(in_b[id], 100) << SettingName(GetParam()) << " object " << id << " from B";
    }
    // Most of the image is measured (walls, floor and furniture within range).
    std::size_t measured = 0;
    for (const std::uint16_t mm : a.depth_mm) measured += mm != 0;
    EXPECT_GT(measured, a.depth_mm.size() / 2);
  }
}

TEST_P(SettingTest, ViewpointsAreThoseOfTheThesis) {
  const PinholeIntrinsics K = KinectIntrinsics();
  const SettingScene s = MakeSetting(GetParam(), 1);
  const Eigen::Vector3d eye_a = s.X_WorldCameraA.translation(), eye_b = s.X_WorldCameraB.translation();
  EXPECT_GE(eye_a.z(), 1.1);
  EXPECT_LE(eye_a.z(), 1.4);
  const double horizontal = std::hypot(s.surface_point_m.x() - eye_a.x(), s.surface_point_m.y() - eye_a.y());
  EXPECT_GE(horizontal, 1.2);
  EXPECT_LE(horizontal, 2.0);
  EXPECT_LT(s.X_WorldCameraA.linear().col(2).z(), -0.15) << "A looks down at the furniture";
  EXPECT_LT(s.X_WorldCameraB.linear().col(2).z(), -0.15) << "B looks down at the furniture";
  const double displacement = (eye_b - eye_a).norm();
  EXPECT_GE(displacement, 0.40);
  EXPECT_LE(displacement, 0.50);
  const double turn_deg =
      std::abs(std::remainder(HeadingRad(s.X_WorldCameraB) - HeadingRad(s.X_WorldCameraA), 2 * M_PI)) * 180 / M_PI;
  EXPECT_GE(turn_deg, 30.0);
  EXPECT_LE(turn_deg, 40.0);
  for (const Eigen::Isometry3d& X : {s.X_WorldCameraA, s.X_WorldCameraB}) {
    const std::optional<Eigen::Vector2d> px = Project(K, X, s.surface_point_m);
    ASSERT_TRUE(px.has_value());
    EXPECT_GT(px->x(), 40.0);
    EXPECT_LT(px->x(), K.width - 40.0);
    EXPECT_GT(px->y(), 40.0);
    EXPECT_LT(px->y(), K.height - 40.0);
    // Rotation is proper and orthonormal.
    EXPECT_NEAR(X.linear().determinant(), 1.0, 1e-9);
  }
}

TEST_P(SettingTest, SmallObjectsStandOnTheSurface) {
  const SettingScene s = MakeSetting(GetParam(), 5);
  std::vector<int> small(s.movable_ids.begin(), s.movable_ids.end());
  if (GetParam() == Setting::kDO || GetParam() == Setting::kKI1 || GetParam() == Setting::kKI2 ||
      GetParam() == Setting::kSO) {
    small.erase(small.begin());  // the characteristic object (door, chair, drawer, person) comes first
  }
  small.push_back(s.thin_object_id);
  small.push_back(s.tall_object_id);
  for (const int id : small) {
    int primitives = 0;
    for (const Primitive& p : s.scene.primitives) {
      if (p.object_id != id) continue;
      ++primitives;
      const double bottom = p.X_WorldPrim.translation().z() - 0.5 * p.size_m.z();  // upright objects
      EXPECT_NEAR(bottom, s.surface_point_m.z(), 1e-9) << id;
      EXPECT_LT((p.X_WorldPrim.translation().head<2>() - s.surface_point_m.head<2>()).norm(), 0.6) << id;
    }
    EXPECT_GE(primitives, 1) << id;
  }
  // The thin object is about 1 cm high, the tall one about 30 cm.
  for (const Primitive& p : s.scene.primitives) {
    if (p.object_id == s.thin_object_id) {
      EXPECT_NEAR(p.size_m.z(), 0.01, 1e-12);
    }
    if (p.object_id == s.tall_object_id) {
      EXPECT_NEAR(p.size_m.z(), 0.30, 0.031);
    }
  }
}

TEST_P(SettingTest, SeedVariesTheObjectsDeterministically) {
  const nlohmann::json one = SceneToJson(MakeSetting(GetParam(), 1).scene);
  EXPECT_EQ(SceneToJson(MakeSetting(GetParam(), 1).scene), one);
  EXPECT_NE(SceneToJson(MakeSetting(GetParam(), 2).scene), one);
}

INSTANTIATE_TEST_SUITE_P(AllSettings, SettingTest, testing::ValuesIn(AllSettings()),
                         [](const testing::TestParamInfo<Setting>& param) {
                           return std::string(SettingName(param.param));
                         });

TEST(ApartmentTest, KinectIntrinsics) {
  const PinholeIntrinsics K = KinectIntrinsics();
  EXPECT_EQ(K.width, 640);
  EXPECT_EQ(K.height, 480);
  EXPECT_EQ(K.fx, 525.0);
  EXPECT_EQ(K.fy, 525.0);
  EXPECT_EQ(K.cx, 319.5);
  EXPECT_EQ(K.cy, 239.5);
}

}  // namespace
}  // namespace anchordb::sim
