// The structured-light artefacts of SensorModel, each isolated by switching the others off: flying pixels,
// disparity quantisation, clustered dropouts, correlated noise, lateral jitter; and the kind sensor's frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <vector>

#include "sim/renderer.h"
#include "tests/sim/sim_test_scenes.h"

namespace anchordb::sim {
namespace {

// Only the artefacts switched on here (the master `noise` switch on, every single one off).
SensorModel Only(void (*enable)(SensorModel&)) {
  SensorModel s = KindSensor();
  s.axial_noise = false;
  enable(s);
  return s;
}

// A 40 x 40 cm box 1.2 m before the camera in front of a wall at 2.5 m.
Scene BoxBeforeWall() {
  return SceneOf({MakeBox(3, {3.0, 0.0, 1.0}, {1.0, 20.0, 20.0}), MakeBox(8, {1.25, 0.0, 1.0}, {0.1, 0.4, 0.4})});
}

// Whether the noiseless depth jumps by more than 10 cm within `r` pixels of (u, v).
bool NearDiscontinuity(const Frame& exact, int u, int v, int r) {
  float lo = 1e9f, hi = 0.0f;
  for (int y = std::max(0, v - r); y <= std::min(exact.height - 1, v + r); ++y) {
    for (int x = std::max(0, u - r); x <= std::min(exact.width - 1, u + r); ++x) {
      const float z = exact.true_depth_m[Index(exact, x, y)];
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  }
  return hi - lo > 0.1f;
}

TEST(SensorArtefactsTest, FlyingPixelsAppearOnlyAtDiscontinuitiesAndLieBetweenTheSurfaces) {
  const Scene scene = BoxBeforeWall();
  const SensorModel sensor = Only([](SensorModel& s) { s.flying_pixels = true; });
  const Frame exact = Render(scene, Kinect(), CameraLookingAlongX(), Noiseless(), kSeed);
  const Frame f = Render(scene, Kinect(), CameraLookingAlongX(), sensor, kSeed);
  std::size_t edge = 0, mixed = 0, dropped = 0;
  for (int v = 0; v < f.height; ++v) {
    for (int u = 0; u < f.width; ++u) {
      const std::size_t i = Index(f, u, v);
      const bool near_edge = NearDiscontinuity(exact, u, v, sensor.flying_band_px);
      edge += near_edge && exact.depth_mm[i] != 0;
      if (exact.depth_mm[i] == 0) continue;  // shadow: nothing to mix
      if (f.depth_mm[i] == exact.depth_mm[i]) continue;
      ASSERT_TRUE(near_edge) << "artefact away from any discontinuity at " << u << "," << v;
      if (f.depth_mm[i] == 0) {
        ++dropped;
        continue;
      }
      ++mixed;
      EXPECT_GE(f.depth_mm[i], 1200) << u << "," << v;  // between the box front (1.2 m) and the wall (2.5 m)
      EXPECT_LE(f.depth_mm[i], 2500) << u << "," << v;
    }
  }
  ASSERT_GT(edge, 1000u);
  // Of the edge pixels ~30 % mix (less the few whose draw lands on their own depth) and ~20 % drop.
  EXPECT_NEAR(static_cast<double>(mixed) / edge, sensor.flying_fraction, 0.06);
  EXPECT_NEAR(static_cast<double>(dropped) / edge, sensor.edge_dropout_fraction, 0.05);
  // Switched off, the frame is the exact one.
  EXPECT_EQ(Render(scene, Kinect(), CameraLookingAlongX(), Only([](SensorModel&) {}), kSeed).depth_mm, exact.depth_mm);
}

// Mean gap between the distinct depths measured within +-6 % of `z_mm` on a slanted wall.
double MeanDepthStepMm(const Frame& f, double z_mm) {
  std::set<int> values;
  for (const std::uint16_t d : f.depth_mm) {
    if (d != 0 && std::abs(d - z_mm) < 0.06 * z_mm) values.insert(d);
  }
  if (values.size() < 3) return 0.0;
  return static_cast<double>(*values.rbegin() - *values.begin()) / static_cast<double>(values.size() - 1);
}

TEST(SensorArtefactsTest, DisparityQuantisationStepGrowsWithTheSquareOfDepth) {
  // A wall turned 17 deg about the vertical covers a continuum of depths, finer per pixel than the steps; the
  // quantised depths come in steps of z^2 * step / (f b) = 2.87 mm at 1 m and 25.9 mm at 3 m (~9x).
  const SensorModel sensor = Only([](SensorModel& s) { s.quantise_disparity = true; });
  const double expected_1m_mm =
      1000.0 * sensor.disparity_step_px / (sensor.disparity_focal_px * sensor.projector_baseline_m);
  double step_mm[2] = {0.0, 0.0};
  for (const int k : {0, 1}) {
    const double z = k == 0 ? 1.0 : 3.0;
    const Scene wall = SceneOf({MakeBox(3, {z, 0.0, 1.0}, {0.05, 6.0, 6.0}, 0.3)});
    step_mm[k] = MeanDepthStepMm(Render(wall, Kinect(), CameraLookingAlongX(), sensor, kSeed), 1000.0 * z);
    EXPECT_NEAR(step_mm[k], expected_1m_mm * z * z, 0.1 * expected_1m_mm * z * z) << z;
    // The exact depths of the same pixels are much finer.
    EXPECT_LT(MeanDepthStepMm(Render(wall, Kinect(), CameraLookingAlongX(), Noiseless(), kSeed), 1000.0 * z),
              0.5 * step_mm[k]);
  }
  EXPECT_NEAR(step_mm[1] / step_mm[0], 9.0, 1.0);
}

TEST(SensorArtefactsTest, SpeckleDropoutsAreClusteredAndChangeFromFrameToFrame) {
  const Scene wall = SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0})});
  const SensorModel sensor = Only([](SensorModel& s) { s.speckle_dropouts = true; });
  const Frame a = Render(wall, Kinect(), CameraLookingAlongX(), sensor, 1);
  const Frame b = Render(wall, Kinect(), CameraLookingAlongX(), sensor, 2);
  std::size_t dropped = 0, right_also = 0, both_frames = 0;
  for (int v = 0; v < a.height; ++v) {
    for (int u = 0; u + 1 < a.width; ++u) {
      if (a.depth_mm[Index(a, u, v)] != 0) continue;
      ++dropped;
      right_also += a.depth_mm[Index(a, u + 1, v)] == 0;
      both_frames += b.depth_mm[Index(b, u, v)] == 0;
    }
  }
  const double fraction = static_cast<double>(dropped) / static_cast<double>(a.depth_mm.size());
  EXPECT_NEAR(fraction, sensor.dropout_fraction, 0.004);
  // Independent dropouts would give P(right neighbour dropped | dropped) = 1 %; clustered ones far more. From
  // frame to frame the pattern is new: P(dropped in b | dropped in a) stays near the base rate.
  EXPECT_GT(static_cast<double>(right_also) / dropped, 0.3);
  EXPECT_LT(static_cast<double>(both_frames) / dropped, 0.05);
}

// Correlation coefficient of the depth errors of pixel pairs (u, v), (u + du, v) over the wall's rows.
double ErrorCorrelation(const Frame& f, const Frame& g, int du) {
  double sxy = 0, sxx = 0, syy = 0, sx = 0, sy = 0, n = 0;
  for (int v = 0; v < f.height; ++v) {
    for (int u = 0; u + du < f.width; ++u) {
      const double x = f.depth_mm[Index(f, u, v)] - 2000.0, y = g.depth_mm[Index(g, u + du, v)] - 2000.0;
      sx += x, sy += y, sxy += x * y, sxx += x * x, syy += y * y, n += 1;
    }
  }
  return (sxy / n - sx / n * sy / n) / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
}

TEST(SensorArtefactsTest, NoiseOfNeighbouringPixelsIsCorrelatedOfDistantOnesAndOtherFramesNot) {
  const Scene wall = SceneOf({MakeBox(3, {2.5, 0.0, 1.0}, {1.0, 20.0, 20.0})});
  const SensorModel sensor = Only([](SensorModel& s) {
    s.axial_noise = true;
    s.correlated_noise_fraction = 0.8;
  });
  const Frame a = Render(wall, Kinect(), CameraLookingAlongX(), sensor, 1);
  const Frame b = Render(wall, Kinect(), CameraLookingAlongX(), sensor, 2);
  EXPECT_GT(ErrorCorrelation(a, a, 1), 0.6);
  EXPECT_LT(std::abs(ErrorCorrelation(a, a, 20)), 0.05);
  EXPECT_LT(std::abs(ErrorCorrelation(a, b, 0)), 0.05);  // frame to frame independent
  // White noise only (the kind sensor): neighbours are independent too.
  const Frame w = Render(wall, Kinect(), CameraLookingAlongX(), KindSensor(), 1);
  EXPECT_LT(std::abs(ErrorCorrelation(w, w, 1)), 0.02);
}

TEST(SensorArtefactsTest, LateralJitterMovesEdgesByAboutNguyensSigmaAndKeepsTheTruth) {
  const Scene scene = BoxBeforeWall();
  const SensorModel sensor = Only([](SensorModel& s) { s.lateral_jitter = true; });
  const Frame exact = Render(scene, Kinect(), CameraLookingAlongX(), Noiseless(), kSeed);
  const Frame f = Render(scene, Kinect(), CameraLookingAlongX(), sensor, kSeed);
  EXPECT_EQ(f.object_id, exact.object_id);
  EXPECT_EQ(f.true_depth_m, exact.true_depth_m);
  // The box's right edge (the side the projector lights) per row: where the measured depth leaves the box.
  double sum = 0, sum2 = 0, n = 0;
  for (int v = 180; v <= 300; ++v) {
    int exact_u = -1, measured_u = -1;
    for (int u = 320; u < f.width; ++u) {
      if (exact_u < 0 && exact.depth_mm[Index(exact, u, v)] > 2000) exact_u = u;
      if (measured_u < 0 && f.depth_mm[Index(f, u, v)] > 2000) measured_u = u;
    }
    ASSERT_GT(exact_u, 320);
    const double e = measured_u - exact_u;
    sum += e, sum2 += e * e, n += 1;
  }
  const double sd = std::sqrt(sum2 / n - sum * sum / n / n);
  // round(N(0, 0.8)) has sd 0.85 px; the correlated offsets make 121 rows fewer independent draws.
  EXPECT_GT(sd, 0.4);
  EXPECT_LT(sd, 1.4);
}

TEST(SensorArtefactsTest, KindSensorKeepsTheEarlierRenderersFramesBitForBit) {
  // FNV-1a of the depth of TA and CA from viewpoint A, seed 7, computed with the renderer of commit 39a214d (whose
  // default sensor is KindSensor()).
  std::uint64_t h = 1469598103934665603ull;
  for (const Setting setting : {Setting::kTA, Setting::kCA}) {
    const SettingScene s = MakeSetting(setting, 1);
    const Frame f = Render(s.scene, Kinect(), s.X_WorldCameraA, KindSensor(), 7);
    for (const std::uint16_t d : f.depth_mm) h = (h ^ d) * 1099511628211ull;
  }
  EXPECT_EQ(h, 16949234427066397619ull);
}

TEST(SensorArtefactsTest, OutOfRangeSensorParametersAreRejected) {
  const Scene scene = BoxBeforeWall();
  const auto bad = [&](void (*edit)(SensorModel&)) {
    SensorModel s;
    edit(s);
    EXPECT_THROW(Render(scene, Kinect(), CameraLookingAlongX(), s, kSeed), std::invalid_argument);
  };
  bad([](SensorModel& s) { s.correlated_noise_fraction = 1.5; });
  bad([](SensorModel& s) { s.correlated_noise_spacing_px = 0.5; });
  bad([](SensorModel& s) { s.disparity_step_px = 0.0; });
  bad([](SensorModel& s) { s.projector_baseline_m = 0.0; });
  bad([](SensorModel& s) { s.flying_fraction = 0.9; });
  bad([](SensorModel& s) { s.dropout_fraction = 1.0; });
  bad([](SensorModel& s) { s.flying_band_px = 0; });
}

}  // namespace
}  // namespace anchordb::sim
