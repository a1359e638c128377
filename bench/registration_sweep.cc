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
    views.push_back({rs::Cloud(a, K, Isometry3d::Identity()),
                     engine::PrepareIcpTarget(rs::Cloud(b, K, Isometry3d::Identity()), engine::IcpParams{})});
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
  return 0;
}
