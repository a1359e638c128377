#include "sim/renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "sim/apartment.h"
#include "tests/sim/sim_test_scenes.h"

namespace anchordb::sim {
namespace {

// Optical-frame ray direction of pixel (u, v).
Eigen::Vector3d PixelRay(const PinholeIntrinsics& K, int u, int v) {
  return Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
}

bool NearHalfMillimetre(double z_m) {
  const double mm = z_m * 1000.0;
  return std::abs(mm - std::floor(mm) - 0.5) < 1e-4;
}

TEST(RendererTest, WallFacingTheCameraGivesTheExactDepthEverywhere) {
  const Scene scene = SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0})});  // front face at x = 2 m
  const Frame f = Render(scene, Kinect(), CameraLookingAlongX(), Noiseless(), kSeed);
  ASSERT_EQ(f.width, 640);
  ASSERT_EQ(f.height, 480);
  ASSERT_EQ(f.depth_mm.size(), 640u * 480u);
  for (std::size_t i = 0; i < f.depth_mm.size(); ++i) {
    ASSERT_EQ(f.depth_mm[i], 2000) << "pixel " << i;
    ASSERT_EQ(f.object_id[i], 3);
    ASSERT_FLOAT_EQ(f.true_depth_m[i], 2.0f);
  }
}

TEST(RendererTest, RotatedBoxFaceGivesTheAnalyticDepth) {
  // A box turned 30 deg about world z; its front face is the plane through p0 with normal n (world).
  const double yaw = 30.0 * M_PI / 180.0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d p0(2.0, 0.0, 1.0);
  const Eigen::Vector3d n = R * Eigen::Vector3d(-1.0, 0.0, 0.0);
  const Scene scene = SceneOf({MakeBox(4, p0 - 0.25 * n, {0.5, 12.0, 12.0}, yaw)});
  const Eigen::Isometry3d X_WC = CameraLookingAlongX();
  const PinholeIntrinsics K = Kinect();
  const Frame f = Render(scene, K, X_WC, Noiseless(), kSeed);
  int checked = 0;
  for (int v = 0; v < K.height; v += 7) {
    for (int u = 0; u < K.width; u += 5) {
      const Eigen::Vector3d d_W = X_WC.linear() * PixelRay(K, u, v);
      const double z = n.dot(p0 - X_WC.translation()) / n.dot(d_W);  // ray parameter = optical z (d_C.z = 1)
      const std::size_t i = Index(f, u, v);
      ASSERT_EQ(f.object_id[i], 4);
      EXPECT_NEAR(f.true_depth_m[i], z, 1e-5);
      if (!NearHalfMillimetre(z)) {
        EXPECT_EQ(f.depth_mm[i], static_cast<std::uint16_t>(std::lround(z * 1000.0))) << "u " << u << " v " << v;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 5000);
}

TEST(RendererTest, CylinderMantleGivesTheAnalyticDepth) {
  const double r = 0.3, cx = 3.0, height = 1.0;
  const Scene scene = SceneOf({MakeCylinder(5, {cx, 0.0, 1.0}, r, height)});
  const PinholeIntrinsics K = Kinect();
  const Frame f = Render(scene, K, CameraLookingAlongX(), Noiseless(), kSeed);
  int on_mantle = 0;
  for (int v = 0; v < K.height; v += 3) {
    for (int u = 0; u < K.width; ++u) {
      // World ray from (0, 0, 1) along (1, -x, -y); mantle: (t - cx)^2 + (t x)^2 = r^2.
      const Eigen::Vector3d d = PixelRay(K, u, v);
      const double a = 1.0 + d.x() * d.x(), b = -2.0 * cx, c = cx * cx - r * r;
      const double disc = b * b - 4.0 * a * c;
      const std::size_t i = Index(f, u, v);
      if (disc < 0.0) {
        if (disc < -1e-3) {
          EXPECT_EQ(f.object_id[i], 0) << u << "," << v;
        }
        continue;
      }
      const double t = (-b - std::sqrt(disc)) / (2.0 * a);
      const double dz = std::abs(t * d.y());                  // height above/below the cylinder centre
      if (dz > 0.5 * height - 1e-3 || disc < 1e-3) continue;  // cap or silhouette edge: not the mantle, or too close
      ASSERT_EQ(f.object_id[i], 5) << u << "," << v;
      EXPECT_NEAR(f.true_depth_m[i], t, 1e-5);
      if (!NearHalfMillimetre(t) && f.depth_mm[i] != 0) {
        EXPECT_EQ(f.depth_mm[i], static_cast<std::uint16_t>(std::lround(t * 1000.0)));
      }
      ++on_mantle;
    }
  }
  EXPECT_GT(on_mantle, 3000);
}

TEST(RendererTest, CylinderCapSeenFromAboveGivesTheAnalyticDepth) {
  // Looking straight down from 3 m at a cylinder whose top is at 1 m: the cap is 2 m away.
  const Scene scene = SceneOf({MakeCylinder(6, {0.0, 0.0, 0.5}, 0.5, 1.0)});
  const PinholeIntrinsics K = Kinect();
  const Frame f = Render(scene, K, LookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}), Noiseless(), kSeed);
  int on_cap = 0;
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const Eigen::Vector3d d = PixelRay(K, u, v);
      const double radial_at_cap = 2.0 * std::hypot(d.x(), d.y());
      const std::size_t i = Index(f, u, v);
      if (radial_at_cap < 0.5 - 1e-3) {
        ASSERT_EQ(f.object_id[i], 6);
        ASSERT_EQ(f.depth_mm[i], 2000);
        ++on_cap;
      }
    }
  }
  EXPECT_GT(on_cap, 20000);
}

TEST(RendererTest, ObjectIdsMarkWhatEachPixelHits) {
  // Seen from the camera, +world y is to the left (u < cx).
  const Scene scene =
      SceneOf({MakeBox(7, {2.25, 0.3, 1.0}, {0.5, 0.4, 0.4}), MakeBox(9, {2.25, -0.3, 1.0}, {0.5, 0.4, 0.4})});
  const PinholeIntrinsics K = Kinect();
  const Frame f = Render(scene, K, CameraLookingAlongX(), Noiseless(), kSeed);
  const int v = 240;
  // Front faces at 2 m: box 7 covers u in [188.25, 293.25], box 9 u in [345.75, 450.75]. Their inner side faces
  // (world y = +-0.1, x from 2 to 2.5 m) are seen too, up to u = 298.5 and from u = 340.5.
  for (int u = 0; u < K.width; ++u) {
    const std::size_t i = Index(f, u, v);
    int expected = -1;  // silhouette pixels are not checked
    if (u > 189 && u < 298) expected = 7;
    if (u > 341 && u < 450) expected = 9;
    if (u < 187 || (u > 299 && u < 340) || u > 451) expected = 0;
    if (expected < 0) continue;
    EXPECT_EQ(f.object_id[i], expected) << "u " << u;
    if (expected == 0) {
      EXPECT_EQ(f.depth_mm[i], 0);
      EXPECT_EQ(f.true_depth_m[i], 0.0f);
    } else if (u < 293 || u > 346) {
      EXPECT_EQ(f.true_depth_m[i], 2.0f);
      EXPECT_EQ(f.depth_mm[i], 2000);
    }
  }
  // Rows above and below the boxes see nothing.
  EXPECT_EQ(f.object_id[Index(f, 240, 0)], 0);
  EXPECT_EQ(f.object_id[Index(f, 240, 479)], 0);
}

TEST(RendererTest, NothingIsMeasuredOutsideTheRange) {
  const PinholeIntrinsics K = Kinect();
  for (const double distance : {6.0, 0.4}) {
    const Scene scene = SceneOf({MakeBox(3, {distance + 0.5, 0.0, 1.0}, {1.0, 30.0, 30.0})});
    const Frame f = Render(scene, K, CameraLookingAlongX(), SensorModel{}, kSeed);
    for (std::size_t i = 0; i < f.depth_mm.size(); ++i) {
      ASSERT_EQ(f.depth_mm[i], 0) << "wall at " << distance;
      ASSERT_EQ(f.object_id[i], 3) << "ground truth is kept where depth is dropped";
      ASSERT_GT(f.true_depth_m[i], 0.0f);
    }
  }
  // Just inside the range the wall is measured.
  const Scene scene = SceneOf({MakeBox(3, {4.9 + 0.5, 0.0, 1.0}, {1.0, 30.0, 30.0})});
  const Frame f = Render(scene, K, CameraLookingAlongX(), Noiseless(), kSeed);
  EXPECT_EQ(f.depth_mm[Index(f, 320, 240)], 4900);
}

TEST(RendererTest, FloorSeenAtGrazingAnglesGetsNoDepth) {
  // A camera 0.3 m above a huge floor, looking horizontally: rows just below the horizon see the floor far away
  // and almost edge-on.
  const Scene scene = SceneOf({MakeBox(1, {900.0, 0.0, -0.05}, {2000.0, 2000.0, 0.1})});
  const PinholeIntrinsics K = Kinect();
  SensorModel sensor = Noiseless();
  sensor.max_range_m = 1000.0;  // isolate the incidence rule from the range rule
  const Frame f = Render(scene, K, CameraLookingAlongX(0.3), sensor, kSeed);
  int dropped = 0, measured = 0;
  for (int v = 241; v < K.height; ++v) {
    for (int u = 0; u < K.width; u += 4) {
      const Eigen::Vector3d d = PixelRay(K, u, v);
      const double incidence = std::acos(d.y() / d.norm());  // floor normal is optical -y
      const std::size_t i = Index(f, u, v);
      ASSERT_EQ(f.object_id[i], 1);
      if (std::abs(incidence - sensor.max_incidence_rad) < 1e-3) continue;
      if (incidence > sensor.max_incidence_rad) {
        EXPECT_EQ(f.depth_mm[i], 0) << u << "," << v;
        ++dropped;
      } else {
        EXPECT_GT(f.depth_mm[i], 0) << u << "," << v;
        ++measured;
      }
    }
  }
  EXPECT_GT(dropped, 1000);
  EXPECT_GT(measured, 1000);
  // The row just below the horizon (floor ~300 m away, 89.9 deg incidence) is entirely dropped.
  for (int u = 0; u < K.width; ++u) {
    EXPECT_EQ(f.object_id[Index(f, u, 240)], 1);
    EXPECT_EQ(f.depth_mm[Index(f, u, 240)], 0);
  }
}

TEST(RendererTest, ProjectorShadowsTheBackgroundBesideASmallerBoxInFront) {
  // Back wall at 2 m, a 20 x 20 cm box 1 m in front of the camera. The projector sits 7.5 cm to the camera's
  // right (+x optical = world -y), so it cannot light a band of the wall just left of the box in the image:
  // wall points at optical x in [-0.275, -0.2] m (u in [247.3, 267.0]), while the camera's view of the wall
  // ends at x = -0.2 (the box's silhouette). Right of the box nothing is shadowed.
  const Scene scene =
      SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0}), MakeBox(8, {1.05, 0.0, 1.0}, {0.1, 0.2, 0.2})});
  const PinholeIntrinsics K = Kinect();
  const Frame with_shadow = Render(scene, K, CameraLookingAlongX(), Noiseless(), kSeed);
  SensorModel no_shadow = Noiseless();
  no_shadow.shadow = false;
  const Frame without_shadow = Render(scene, K, CameraLookingAlongX(), no_shadow, kSeed);
  for (int v = 200; v <= 280; v += 10) {  // rows through the box (it spans v in [187, 292])
    for (int u = 0; u < K.width; ++u) {
      const std::size_t i = Index(with_shadow, u, v);
      EXPECT_EQ(with_shadow.object_id[i], without_shadow.object_id[i]);
      EXPECT_GT(without_shadow.depth_mm[i], 0);
      if (u >= 249 && u <= 265) {
        EXPECT_EQ(with_shadow.object_id[i], 3) << u << "," << v;
        EXPECT_EQ(with_shadow.depth_mm[i], 0) << "shadow expected at " << u << "," << v;
      } else if (u <= 245 || u >= 269) {
        EXPECT_GT(with_shadow.depth_mm[i], 0) << "no shadow expected at " << u << "," << v;
      }
    }
  }
  // Above the box (rows outside its projector silhouette) there is no shadow.
  for (int u = 0; u < K.width; ++u) EXPECT_GT(with_shadow.depth_mm[Index(with_shadow, u, 100)], 0);
}

TEST(RendererTest, NoiseOnAFlatWallAtTwoMetresMatchesTheSensorModel) {
  // The kind sensor (white noise only) and the default one (correlated noise, disparity quantisation, whose
  // rounding comes out of the Gaussian budget) both keep Nguyen's sigma; the default one drops ~1 % of pixels.
  const Scene scene = SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0})});
  for (const bool kind : {true, false}) {
    const Frame f = Render(scene, Kinect(), CameraLookingAlongX(), kind ? KindSensor() : SensorModel{}, kSeed);
    double sum = 0.0, sum2 = 0.0, n = 0.0;
    for (const std::uint16_t mm : f.depth_mm) {
      if (kind) {
        ASSERT_GT(mm, 0);
      }
      if (mm == 0) continue;
      const double e = mm - 2000.0;
      sum += e;
      sum2 += e * e;
      n += 1.0;
    }
    const double mean_mm = sum / n;
    const double sigma_mm = std::sqrt(sum2 / n - mean_mm * mean_mm);
    const double expected_sigma_mm = 1000.0 * (0.0012 + 0.0019 * (2.0 - 0.4) * (2.0 - 0.4));  // 6.064 mm
    EXPECT_NEAR(sigma_mm, expected_sigma_mm, 0.15 * expected_sigma_mm) << kind;
    EXPECT_NEAR(mean_mm, 0.0, kind ? 0.1 : 0.5) << kind;  // the correlated field has fewer independent draws
    const double dropped = 1.0 - n / static_cast<double>(f.depth_mm.size());
    if (!kind) {
      EXPECT_NEAR(dropped, SensorModel{}.dropout_fraction, 0.004);
    }
  }
}

TEST(RendererTest, SameSeedSameFrameOtherSeedOtherNoise) {
  const SettingScene setting = MakeSetting(Setting::kTA, 1);
  EXPECT_EQ(Render(setting.scene, Kinect(), setting.X_WorldCameraA, SensorModel{}, 7).depth_mm,
            Render(setting.scene, Kinect(), setting.X_WorldCameraA, SensorModel{}, 7).depth_mm);
  // With the kind sensor (no dropouts, jitter or flying pixels) what is dropped does not depend on the seed.
  const Frame a = Render(setting.scene, Kinect(), setting.X_WorldCameraA, KindSensor(), 7);
  const Frame b = Render(setting.scene, Kinect(), setting.X_WorldCameraA, KindSensor(), 7);
  const Frame c = Render(setting.scene, Kinect(), setting.X_WorldCameraA, KindSensor(), 8);
  EXPECT_EQ(a.depth_mm, b.depth_mm);
  EXPECT_EQ(a.object_id, b.object_id);
  EXPECT_EQ(a.true_depth_m, b.true_depth_m);
  EXPECT_EQ(a.object_id, c.object_id);
  EXPECT_EQ(a.true_depth_m, c.true_depth_m);
  std::size_t measured = 0, differing = 0;
  for (std::size_t i = 0; i < a.depth_mm.size(); ++i) {
    if (a.depth_mm[i] == 0) {
      EXPECT_EQ(c.depth_mm[i], 0);  // what is dropped does not depend on the noise
      continue;
    }
    ++measured;
    if (a.depth_mm[i] != c.depth_mm[i]) ++differing;
  }
  EXPECT_GT(differing, measured / 2);
}

TEST(RendererTest, MoveObjectChangesOnlyThatObjectsPixels) {
  const SettingScene setting = MakeSetting(Setting::kTA, 1);
  const int cup = setting.movable_ids.front();
  Scene moved = setting.scene;
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  delta.translation() = Eigen::Vector3d(0.10, 0.05, 0.0);
  MoveObject(moved, cup, delta);
  for (std::size_t k = 0; k < moved.primitives.size(); ++k) {
    const Primitive& before = setting.scene.primitives[k];
    const Primitive& after = moved.primitives[k];
    Eigen::Vector3d expected = before.X_WorldPrim.translation();
    if (before.object_id == cup) expected += delta.translation();
    EXPECT_TRUE(after.X_WorldPrim.translation().isApprox(expected, 1e-12));
  }

  for (const bool kind : {true, false}) {
  for (const bool shadow : {false, true}) {
    // With noise: the same seed gives the same noise at every pixel. The default sensor's lateral offsets and
    // flying-pixel band let the cup reach pixels a few pixels beside it.
    SensorModel sensor = kind ? KindSensor() : SensorModel{};
    sensor.shadow = shadow;
    const Frame a = Render(setting.scene, Kinect(), setting.X_WorldCameraA, sensor, kSeed);
    const Frame b = Render(moved, Kinect(), setting.X_WorldCameraA, sensor, kSeed);
    const int reach_px = kind ? 0 : 5;
    const auto near_cup = [&](std::size_t i) {
      const int u = static_cast<int>(i % a.width), v = static_cast<int>(i / a.width);
      for (int y = std::max(0, v - reach_px); y <= std::min(a.height - 1, v + reach_px); ++y) {
        for (int x = std::max(0, u - reach_px); x <= std::min(a.width - 1, u + reach_px); ++x) {
          const std::size_t k = Index(a, x, y);
          if (a.object_id[k] == cup || b.object_id[k] == cup) return true;
        }
      }
      return false;
    };
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.depth_mm.size(); ++i) {
      if (a.depth_mm[i] == b.depth_mm[i] && a.object_id[i] == b.object_id[i]) continue;
      ++changed;
      const bool cup_pixel = near_cup(i);
      // With shadows, the cup's projector shadow moves with it: such pixels lose or regain their depth.
      const bool shadow_pixel =
          shadow && a.object_id[i] == b.object_id[i] && (a.depth_mm[i] == 0 || b.depth_mm[i] == 0);
      ASSERT_TRUE(cup_pixel || shadow_pixel)
          << "pixel " << i << " changed: id " << a.object_id[i] << " -> " << b.object_id[i];
    }
    EXPECT_GT(changed, 500u);
  }
  }
}

TEST(RendererTest, RemoveObjectDropsItsPrimitivesAndUnknownIdsThrow) {
  SettingScene setting = MakeSetting(Setting::kTA, 1);
  const int book = setting.movable_ids[2];
  RemoveObject(setting.scene, book);
  for (const Primitive& p : setting.scene.primitives) EXPECT_NE(p.object_id, book);
  for (const Object& o : setting.scene.objects) EXPECT_NE(o.id, book);
  const Frame f = Render(setting.scene, Kinect(), setting.X_WorldCameraA, SensorModel{}, kSeed);
  for (const std::int32_t id : f.object_id) ASSERT_NE(id, book);
  EXPECT_THROW(RemoveObject(setting.scene, book), std::invalid_argument);
  EXPECT_THROW(MoveObject(setting.scene, 999, Eigen::Isometry3d::Identity()), std::invalid_argument);
}

TEST(RendererTest, LookAtGivesAnOpticalFrameWithImageYDownwards) {
  const Eigen::Vector3d eye(1.0, 2.0, 1.3), target(2.5, 2.5, 0.7);
  const Eigen::Isometry3d X = LookAt(eye, target);
  EXPECT_TRUE(X.translation().isApprox(eye));
  EXPECT_TRUE(X.linear().col(2).isApprox((target - eye).normalized()));
  EXPECT_NEAR(X.linear().col(0).z(), 0.0, 1e-12);  // image x horizontal
  EXPECT_LT(X.linear().col(1).z(), 0.0);           // image y points down
  EXPECT_NEAR(X.linear().determinant(), 1.0, 1e-12);
  // Straight down and straight up are defined too.
  EXPECT_NEAR(LookAt({0, 0, 3}, {0, 0, 0}).linear().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(LookAt({0, 0, 0}, {0, 0, 3}).linear().determinant(), 1.0, 1e-12);
  EXPECT_THROW(LookAt(eye, eye), std::invalid_argument);
}

TEST(RendererTest, RenderRejectsInvalidInput) {
  const Scene scene = SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0})});
  PinholeIntrinsics K = Kinect();
  K.width = 0;
  EXPECT_THROW(Render(scene, K, CameraLookingAlongX(), SensorModel{}, kSeed), std::invalid_argument);
  K = Kinect();
  K.fx = 0.0;
  EXPECT_THROW(Render(scene, K, CameraLookingAlongX(), SensorModel{}, kSeed), std::invalid_argument);
  Scene bad = scene;
  bad.primitives[0].object_id = 0;
  EXPECT_THROW(Render(bad, Kinect(), CameraLookingAlongX(), SensorModel{}, kSeed), std::invalid_argument);
  bad = scene;
  bad.primitives[0].size_m.y() = -1.0;
  EXPECT_THROW(Render(bad, Kinect(), CameraLookingAlongX(), SensorModel{}, kSeed), std::invalid_argument);
}

TEST(SceneJsonTest, RoundTripKeepsTheSceneAndItsImages) {
  const SettingScene setting = MakeSetting(Setting::kCA, 3);
  const nlohmann::json j = SceneToJson(setting.scene);
  const Scene back = SceneFromJson(nlohmann::json::parse(j.dump()));
  ASSERT_EQ(back.objects.size(), setting.scene.objects.size());
  ASSERT_EQ(back.primitives.size(), setting.scene.primitives.size());
  for (std::size_t k = 0; k < back.objects.size(); ++k) {
    EXPECT_EQ(back.objects[k].id, setting.scene.objects[k].id);
    EXPECT_EQ(back.objects[k].name, setting.scene.objects[k].name);
    EXPECT_EQ(back.objects[k].kind, setting.scene.objects[k].kind);
  }
  for (std::size_t k = 0; k < back.primitives.size(); ++k) {
    EXPECT_EQ(back.primitives[k].object_id, setting.scene.primitives[k].object_id);
    EXPECT_EQ(back.primitives[k].shape, setting.scene.primitives[k].shape);
    EXPECT_TRUE(back.primitives[k].X_WorldPrim.isApprox(setting.scene.primitives[k].X_WorldPrim, 1e-12));
    EXPECT_TRUE(back.primitives[k].size_m.isApprox(setting.scene.primitives[k].size_m, 1e-15));
  }
  const Frame a = Render(setting.scene, Kinect(), setting.X_WorldCameraA, Noiseless(), kSeed);
  const Frame b = Render(back, Kinect(), setting.X_WorldCameraA, Noiseless(), kSeed);
  EXPECT_EQ(a.object_id, b.object_id);
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.depth_mm.size(); ++i) differing += a.depth_mm[i] != b.depth_mm[i];
  EXPECT_LT(differing, 10u);  // only pixels on a rounding edge may flip by the text round trip of the poses
}

TEST(SceneJsonTest, ParsesTheDocumentedFormat) {
  const Scene scene = SceneFromJson(nlohmann::json::parse(R"({"objects":[
      {"id":1,"name":"table","kind":"static","primitives":[
        {"shape":"box","position":[1,2,0.7],"size":[1.2,0.8,0.03]},
        {"shape":"cylinder","position":[1,2,0.35],"orientation":[0,0,0.7071068,0.7071068],"size":[0.05,0.05,0.7]}]},
      {"id":5,"name":"cup","kind":"movable","primitives":[]}]})"));
  ASSERT_EQ(scene.objects.size(), 2u);
  ASSERT_EQ(scene.primitives.size(), 2u);
  EXPECT_EQ(scene.primitives[0].object_id, 1);
  EXPECT_EQ(scene.primitives[1].shape, Shape::kCylinder);
  EXPECT_TRUE(scene.primitives[1].X_WorldPrim.linear().isApprox(
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-6));
  EXPECT_DOUBLE_EQ(scene.primitives[0].size_m.x(), 1.2);
  EXPECT_EQ(scene.objects[1].kind, "movable");
}

TEST(SceneJsonTest, RejectsBadInputWithAClearMessage) {
  const auto object = [](const std::string& primitive) {
    return R"({"objects":[{"id":1,"name":"t","kind":"static","primitives":[)" + primitive + "]}]}";
  };
  const std::string good = R"({"shape":"box","position":[0,0,0],"size":[1,1,1]})";
  ASSERT_NO_THROW(SceneFromJson(nlohmann::json::parse(object(good))));
  const std::vector<std::string> bad = {
      "[]",
      "{}",
      R"({"objects":{}})",
      R"({"objects":[],"extra":1})",
      R"({"objects":[{"id":0,"name":"t","kind":"static","primitives":[]}]})",
      R"({"objects":[{"id":1.5,"name":"t","kind":"static","primitives":[]}]})",
      R"({"objects":[{"id":1,"name":"t","kind":"furniture","primitives":[]}]})",
      R"({"objects":[{"id":1,"kind":"static","primitives":[]}]})",
      R"({"objects":[{"id":1,"name":"t","kind":"static"}]})",
      R"({"objects":[{"id":1,"name":"t","kind":"static","primitives":[]},
                     {"id":1,"name":"u","kind":"static","primitives":[]}]})",
      object(R"({"shape":"sphere","position":[0,0,0],"size":[1,1,1]})"),
      object(R"({"shape":"box","position":[0,0],"size":[1,1,1]})"),
      object(R"({"shape":"box","position":[0,0,"a"],"size":[1,1,1]})"),
      object(R"({"shape":"box","position":[0,0,0],"size":[1,0,1]})"),
      object(R"({"shape":"box","position":[0,0,0],"size":[1,-1,1]})"),
      object(R"({"shape":"cylinder","position":[0,0,0],"size":[0,1,1]})"),
      object(R"({"shape":"box","position":[0,0,0],"orientation":[0,0,0,2],"size":[1,1,1]})"),
      object(R"({"shape":"box","position":[0,0,0],"orientation":[0,0,1],"size":[1,1,1]})"),
      object(R"({"shape":"box","position":[0,0,0],"size":[1,1,1],"colour":"red"})"),
      object(R"({"position":[0,0,0],"size":[1,1,1]})"),
      object(R"(7)"),
  };
  for (const std::string& text : bad) {
    EXPECT_THROW(SceneFromJson(nlohmann::json::parse(text)), std::invalid_argument) << text;
  }
  try {
    SceneFromJson(nlohmann::json::parse(object(R"({"shape":"box","position":[0,0,0],"size":[1,-1,1]})")));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("objects[0].primitives[0].size"), std::string::npos) << e.what();
  }
  Scene orphan;
  orphan.primitives.push_back(MakeBox(2, {0, 0, 0}, {1, 1, 1}));
  EXPECT_THROW(SceneToJson(orphan), std::invalid_argument);
}

}  // namespace
}  // namespace anchordb::sim
