// Registration's calibration (issue 13): a statistical measure of 80 seeded registrations in the sparse room. It
// runs with the evaluations in ./build (-O2): under the sanitizer build's -O0 it took minutes, and the sanitized
// registration code is exercised by tests/engine/registration_test.cc.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "engine/scene/registration.h"
#include "tests/engine/registration_scenes.h"

namespace anchordb::engine {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
namespace rs = registration_scenes;

struct Trial {
  IcpResult result;
  Isometry3d correction_true;  // maps the source onto the target
};

// The remaining error (the true motion after the applied correction) as [t, r].
Vector6d Remaining(const Trial& t) {
  const Isometry3d E = t.correction_true * (t.result.accepted ? t.result.correction.inverse() : Isometry3d::Identity());
  const Eigen::AngleAxisd aa(E.linear());
  Vector6d e;
  e << E.translation(), aa.axis() * aa.angle();
  return e;
}

// The sparse room (sim/, 320 x 240): for localisation errors drawn from the prior itself, the true remaining error
// must lie inside the posterior's 99 % ellipsoid (chi-square, 6 dof, 16.81) in about 99 % of the trials.
TEST(RegistrationTest, TheCovarianceHoldsTheTrueErrorInTheSparseRoom) {
  const PinholeIntrinsics K = rs::Kinect(320, 240);
  const sim::Scene scene = rs::SparseRoom();
  const Isometry3d A = rs::ViewA(), B = rs::ViewB();
  const Vector6d sigma = (Vector6d() << 0.03, 0.03, 0.03, 0.035, 0.035, 0.035).finished();
  const Matrix6d per_camera = Matrix6d(sigma.cwiseProduct(sigma).asDiagonal());
  int inside = 0, trials = 0, accepted = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const sim::Frame earlier = sim::Render(scene, K, A, sim::SensorModel{}, seed);
    const sim::Frame current = sim::Render(scene, K, B, sim::SensorModel{}, 100 + seed);
    const IcpTarget target = PrepareIcpTarget(rs::RegistrationInput(current, K, Isometry3d::Identity()), IcpParams{});
    rs::Rng rng(seed);
    const auto draw = [&](int first) {
      Vector3d v = Vector3d::Zero();
      for (int k = 0; k < 3; ++k) v(k) = sigma(first + k) * rng.Normal();
      return v;
    };
    for (int i = 0; i < 20; ++i) {
      const Isometry3d A_stored = rs::Perturbed(A, draw(0), draw(3));
      const Isometry3d B_stored = rs::Perturbed(B, draw(0), draw(3));
      const Isometry3d X_CE_stored = B_stored.inverse() * A_stored, X_CE_true = B.inverse() * A;
      const Matrix6d prior = RelativePoseCovariance(B_stored, per_camera, A_stored, per_camera);
      Trial t{AlignIcp(rs::RegistrationInput(earlier, K, X_CE_stored), target, prior), X_CE_true * X_CE_stored.inverse()};
      const Vector6d e = Remaining(t);
      const double d2 = e.dot(t.result.covariance.ldlt().solve(e));
      inside += d2 <= 16.81, ++trials, accepted += t.result.accepted;
      if (d2 > 16.81) {
        std::printf("d2 %.1f:", d2);
        for (int k = 0; k < 6; ++k) std::printf(" %.4f/%.4f", e(k), std::sqrt(t.result.covariance(k, k)));
        std::printf(" | %s\n", t.result.verdict.c_str());
      }
    }
  }
  const double fraction = static_cast<double>(inside) / trials;
  RecordProperty("inside_99_ellipsoid", std::to_string(fraction));
  std::printf("calibration: %d of %d inside the 99 %% ellipsoid, %d accepted\n", inside, trials, accepted);
  EXPECT_GE(fraction, 0.95);
  EXPECT_GE(accepted, trials * 9 / 10);
}

}  // namespace
}  // namespace anchordb::engine
