// Registration sweep (issue 13): the sparse room of tests/engine/registration_scenes.h (a table and a box on the
// floor, rendered 640 x 480 by sim/), the earlier view A registered against the current view B (0.5 m away, heading
// turned 35 deg) after A's stored pose was moved by exactly the given error (random directions, 10 seeds), with the
// default prior (3 cm / 0.035 rad per camera, RelativePoseCovariance). Prints, per error, the error of the earlier
// camera after registration (the correction applied only when accepted), mean and worst, the share accepted, and the
// time per AlignIcp. Usage: anchordb_registration_sweep [seeds] [width].
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "engine/scene/registration.h"
#include "tests/engine/registration_scenes.h"

using namespace anchordb;
namespace rs = anchordb::registration_scenes;
using Eigen::Isometry3d;

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 10;
  const int width = argc > 2 ? std::atoi(argv[2]) : 640;
  const PinholeIntrinsics K = rs::Kinect(width, width * 3 / 4);
  const sim::Scene scene = rs::SparseRoom();
  const Isometry3d A = rs::ViewA(), B = rs::ViewB();
  const engine::Matrix6d per_camera = engine::PoseCovarianceFromSigma(0.03, 0.035);
  struct View {
    std::vector<Eigen::Vector3f> earlier_camera;  // A's points in A's own frame
    engine::IcpTarget target;
  };
  std::vector<View> views;
  for (int s = 0; s < seeds; ++s) {
    const sim::Frame a = sim::Render(scene, K, A, sim::SensorModel{}, 1000 + s);
    const sim::Frame b = sim::Render(scene, K, B, sim::SensorModel{}, 2000 + s);
    views.push_back({rs::RegistrationInput(a, K, Isometry3d::Identity()),
                     engine::PrepareIcpTarget(rs::RegistrationInput(b, K, Isometry3d::Identity()), engine::IcpParams{})});
  }
  const double deg = std::numbers::pi / 180.0;
  std::printf("| error given | after: translation mean / worst [cm] | rotation mean / worst [deg] | accepted | CPU ms per AlignIcp |\n");
  std::printf("|---|---|---|---|---|\n");
  double total_ms = 0;
  int total = 0;
  for (const double t_cm : {1.0, 2.0, 3.0, 5.0}) {
    for (const double r_deg : {0.5, 1.0, 2.0, 3.0}) {
      double t_sum = 0, t_max = 0, r_sum = 0, r_max = 0, ms = 0;
      int accepted = 0;
      for (int s = 0; s < seeds; ++s) {
        rs::Rng rng(static_cast<std::uint64_t>(s * 7919 + t_cm * 100 + r_deg * 10));
        const Isometry3d A_stored = rs::Perturbed(A, rng.UnitVector() * t_cm / 100, rng.UnitVector() * r_deg * deg);
        const Isometry3d X_CE_stored = B.inverse() * A_stored, X_CE_true = B.inverse() * A;
        std::vector<Eigen::Vector3f> source = views[s].earlier_camera;
        for (auto& p : source) p = (X_CE_stored * p.cast<double>()).cast<float>();
        const engine::Matrix6d prior = engine::RelativePoseCovariance(B, per_camera, A_stored, per_camera);
        const std::clock_t start = std::clock();
        const engine::IcpResult r = engine::AlignIcp(source, views[s].target, prior);
        ms += 1000.0 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;  // CPU time: the machine is shared
        const Isometry3d estimated = r.accepted ? r.correction * X_CE_stored : X_CE_stored;
        const rs::PoseError e = rs::ErrorOf(estimated, X_CE_true);
        t_sum += e.translation_m, t_max = std::max(t_max, e.translation_m);
        r_sum += e.rotation_rad, r_max = std::max(r_max, e.rotation_rad);
        accepted += r.accepted;
        if (std::getenv("SWEEP_VERBOSE")) {
          std::printf("  seed %d: %s; relative information", s, r.verdict.c_str());
          for (const double l : r.relative_information) std::printf(" %.3g", l);
          std::printf("\n");
        }
      }
      std::printf("| %.0f cm / %.1f deg | %.2f / %.2f | %.2f / %.2f | %d/%d | %.1f |\n", t_cm, r_deg,
                  100 * t_sum / seeds, 100 * t_max, r_sum / seeds / deg, r_max / deg, accepted, seeds, ms / seeds);
      total_ms += ms, total += seeds;
    }
  }
  std::printf("mean time per AlignIcp: %.1f ms over %d alignments\n", total_ms / total, total);
  // Calibration: both cameras' stored poses drawn from the prior itself (3 cm / 0.035 rad per axis); the remaining
  // error (the true relative motion after the correction applied, or all of it) against the reported covariance.
  int inside99 = 0, inside3sigma = 0, trials = 0;
  for (int s = 0; s < seeds; ++s) {
    rs::Rng rng(static_cast<std::uint64_t>(77 + s));
    const auto draw = [&](double sigma) {
      Eigen::Vector3d v;
      for (int k = 0; k < 3; ++k) v(k) = sigma * rng.Normal();
      return v;
    };
    for (int i = 0; i < 20; ++i) {
      const Isometry3d A_stored = rs::Perturbed(A, draw(0.03), draw(0.035));
      const Isometry3d B_stored = rs::Perturbed(B, draw(0.03), draw(0.035));
      const Isometry3d X_CE_stored = B_stored.inverse() * A_stored, X_CE_true = B.inverse() * A;
      std::vector<Eigen::Vector3f> source = views[s].earlier_camera;
      for (auto& p : source) p = (X_CE_stored * p.cast<double>()).cast<float>();
      const engine::IcpResult r =
          engine::AlignIcp(source, views[s].target, engine::RelativePoseCovariance(B_stored, per_camera, A_stored, per_camera));
      const Isometry3d E = X_CE_true * X_CE_stored.inverse() * (r.accepted ? r.correction.inverse() : Isometry3d::Identity());
      const Eigen::AngleAxisd aa(E.linear());
      Eigen::Matrix<double, 6, 1> e;
      e << E.translation(), aa.axis() * aa.angle();
      const double d2 = e.dot(r.covariance.ldlt().solve(e));
      inside99 += d2 <= 16.81;
      if (std::getenv("SWEEP_VERBOSE") && d2 > 16.81) {
        std::printf("  outside: d2 %.1f accepted %d unobservable %d error", d2, r.accepted, r.unobservable_directions);
        for (int k = 0; k < 6; ++k) std::printf(" %.4f/%.4f", e(k), std::sqrt(r.covariance(k, k)));
        std::printf("\n");
      }
      bool all = true;
      for (int k = 0; k < 6; ++k) all = all && std::abs(e(k)) <= 3.0 * std::sqrt(r.covariance(k, k));
      inside3sigma += all, ++trials;
    }
  }
  std::printf("calibration: %d of %d inside the 99 %% ellipsoid (chi-square 6 dof, 16.81), %d of %d within 3 sigma on "
              "every axis\n", inside99, trials, inside3sigma, trials);
  return 0;
}
