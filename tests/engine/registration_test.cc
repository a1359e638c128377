// Registration that knows what it cannot see (issue 13, thesis 3.3.2): point-to-plane MAP registration keeps the
// prior pose in the directions the geometry leaves unobservable (a plane, two parallel planes, a corridor), corrects
// the rest, rejects corrections inconsistent with the prior, and reports a covariance that holds the true error.
#include "engine/scene/registration.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "tests/engine/registration_scenes.h"

namespace anchordb::engine {
namespace registration_test {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
namespace rs = registration_scenes;

constexpr double kDeg = 3.14159265358979 / 180.0;

// A rectangle of points (spacing 1 cm) at `origin` spanned by the unit axes a and b, with seeded noise (1 mm)
// along its normal; `offset` shifts the sampling grid so that two clouds never share points.
void AddPatch(std::vector<Eigen::Vector3f>& out, const Vector3d& origin, const Vector3d& a, const Vector3d& b,
              double extent_a_m, double extent_b_m, rs::Rng& rng, double offset = 0.0) {
  const Vector3d n = a.cross(b).normalized();
  for (double s = offset; s < extent_a_m; s += 0.01) {
    for (double t = offset; t < extent_b_m; t += 0.01) {
      out.push_back((origin + s * a + t * b + 0.001 * rng.Normal() * n).cast<float>());
    }
  }
}

// Optical frame (x right, y down, z forward): the floor at y = +1.2, a table top at y = +0.5.
using SceneFn = void (*)(std::vector<Eigen::Vector3f>&, rs::Rng&, double);

void SinglePlane(std::vector<Eigen::Vector3f>& out, rs::Rng& rng, double offset) {
  AddPatch(out, {-1.0, -0.8, 2.0}, Vector3d::UnitX(), Vector3d::UnitY(), 2.0, 1.6, rng, offset);
}
void FloorAndTableTop(std::vector<Eigen::Vector3f>& out, rs::Rng& rng, double offset) {
  AddPatch(out, {-1.5, 1.2, 1.0}, Vector3d::UnitX(), Vector3d::UnitZ(), 3.0, 2.5, rng, offset);
  AddPatch(out, {-0.6, 0.5, 1.5}, Vector3d::UnitX(), Vector3d::UnitZ(), 1.2, 0.8, rng, offset);
}
void Corridor(std::vector<Eigen::Vector3f>& out, rs::Rng& rng, double offset) {  // along the optical axis
  AddPatch(out, {-0.8, 1.2, 1.0}, Vector3d::UnitX(), Vector3d::UnitZ(), 1.6, 2.5, rng, offset);
  AddPatch(out, {-0.8, -0.8, 1.0}, Vector3d::UnitY(), Vector3d::UnitZ(), 2.0, 2.5, rng, offset);
  AddPatch(out, {0.8, -0.8, 1.0}, Vector3d::UnitY(), Vector3d::UnitZ(), 2.0, 2.5, rng, offset);
}
void RoomCorner(std::vector<Eigen::Vector3f>& out, rs::Rng& rng, double offset) {
  AddPatch(out, {-1.5, 1.2, 1.0}, Vector3d::UnitX(), Vector3d::UnitZ(), 2.5, 2.0, rng, offset);  // floor
  AddPatch(out, {-1.5, -0.8, 3.0}, Vector3d::UnitX(), Vector3d::UnitY(), 2.5, 2.0, rng, offset);  // back wall
  AddPatch(out, {1.0, -0.8, 1.0}, Vector3d::UnitY(), Vector3d::UnitZ(), 2.0, 2.0, rng, offset);   // side wall
}

struct Trial {
  IcpResult result;
  Isometry3d correction_true;  // maps the source onto the target
};

std::string Eigenvalues(const IcpResult& r) {
  std::string out = r.verdict + "; relative information";
  for (const double l : r.relative_information) out += " " + std::to_string(l);
  return out;
}

// The source is the scene seen from a camera off by X_true: the correction that registers it is X_true.
Trial Register(SceneFn scene, const Isometry3d& X_true, const Matrix6d& prior) {
  rs::Rng rng(7);
  std::vector<Eigen::Vector3f> target, source;
  scene(target, rng, 0.0);
  scene(source, rng, 0.005);
  for (auto& p : source) p = (X_true.inverse() * p.cast<double>()).cast<float>();
  IcpParams params;
  return {AlignIcp(source, PrepareIcpTarget(target, params), prior), X_true};
}

Isometry3d Motion(const Vector3d& t_m, const Vector3d& r_rad) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(r_rad.norm(), r_rad.normalized()).toRotationMatrix();
  X.translation() = t_m;
  return X;
}

// The remaining error (the true motion after the applied correction) as [t, r].
Vector6d Remaining(const Trial& t) {
  const Isometry3d E = t.correction_true * (t.result.accepted ? t.result.correction.inverse() : Isometry3d::Identity());
  const Eigen::AngleAxisd aa(E.linear());
  Vector6d e;
  e << E.translation(), aa.axis() * aa.angle();
  return e;
}

const Matrix6d kPrior = PoseCovarianceFromSigma(0.04, 0.04);

TEST(RegistrationTest, APlaneCorrectsOnlyItsNormalOffsetAndKeepsThePriorInPlane) {
  const Trial t = Register(SinglePlane, Motion({0.03, -0.02, 0.025}, {0, 0, 0.03}), kPrior);
  ASSERT_TRUE(t.result.accepted) << t.result.verdict;
  EXPECT_EQ(t.result.unobservable_directions, 3) << t.result.verdict;  // x, y and the turn about the normal
  EXPECT_NEAR(t.result.correction.translation().z(), 0.025, 0.002);
  EXPECT_LT(t.result.correction.translation().head<2>().norm(), 0.001);  // in-plane: the prior (no motion)
  EXPECT_LT(Eigen::AngleAxisd(t.result.correction.linear()).angle(), 0.002);
  // What it cannot see keeps the prior's uncertainty; what it saw is known to a few mm.
  EXPECT_NEAR(t.result.covariance(0, 0), kPrior(0, 0), 1e-3 * kPrior(0, 0) + 1e-5);
  EXPECT_LT(std::sqrt(t.result.covariance(2, 2)), 0.005);
  EXPECT_TRUE(t.result.correction.matrix().allFinite());
}

TEST(RegistrationTest, FloorAndTableTopKeepThePriorAlongTheirSlidingDirections) {
  const std::vector<Vector3d> offsets_m = {Vector3d(0.03, -0.02, 0.02), Vector3d(-0.04, 0.01, 0.03)};
  for (const Vector3d& t_m : offsets_m) {
    const Trial t = Register(FloorAndTableTop, Motion(t_m, Vector3d(0.01, 0.02, -0.015)), kPrior);
    ASSERT_TRUE(t.result.accepted) << t.result.verdict;
    EXPECT_EQ(t.result.unobservable_directions, 3) << Eigenvalues(t.result);  // x, z and the turn about y
    const Vector6d before = Remaining({IcpResult{}, t.correction_true}), after = Remaining(t);
    for (const int k : {0, 2, 4}) EXPECT_LE(std::abs(after(k)), std::abs(before(k)) + 0.001) << "direction " << k;
    EXPECT_LT(std::abs(after(1)), 0.002);                        // the normal offset is corrected
    EXPECT_LT(std::abs(after(3)), 0.002);  // and so are the tilts (about x and z)
    EXPECT_LT(std::abs(after(5)), 0.002);
  }
}

TEST(RegistrationTest, ACorridorLeavesOnlyItsAxisUnobservable) {
  const Trial t = Register(Corridor, Motion({0.02, 0.03, 0.04}, {0.01, -0.02, 0.02}), kPrior);
  ASSERT_TRUE(t.result.accepted) << t.result.verdict;
  EXPECT_EQ(t.result.unobservable_directions, 1) << Eigenvalues(t.result);
  const Vector6d after = Remaining(t);
  EXPECT_NEAR(t.result.correction.translation().z(), 0.0, 0.003);  // along the corridor: the prior
  EXPECT_LT(after.head<2>().cwiseAbs().maxCoeff(), 0.003);
  EXPECT_LT(after.tail<3>().norm(), 0.2 * kDeg);
}

TEST(RegistrationTest, ARoomCornerIsFullyCorrectedFromFiveCentimetresAndThreeDegrees) {
  const Matrix6d prior = PoseCovarianceFromSigma(0.03 * std::sqrt(2.0), 0.035 * std::sqrt(2.0));
  rs::Rng rng(11);
  for (int i = 0; i < 4; ++i) {
    const Trial t = Register(RoomCorner, Motion(0.05 * rng.UnitVector(), 3 * kDeg * rng.UnitVector()), prior);
    ASSERT_TRUE(t.result.accepted) << t.result.verdict;
    EXPECT_EQ(t.result.unobservable_directions, 0);
    const Vector6d after = Remaining(t);
    EXPECT_LT(after.head<3>().norm(), 0.01) << t.result.verdict;
    EXPECT_LT(after.tail<3>().norm(), 0.5 * kDeg) << t.result.verdict;
  }
}

TEST(RegistrationTest, ACorrectionInconsistentWithThePriorIsRejected) {
  // A 12 cm offset the geometry sees clearly, against a prior of 1 cm / 0.5 deg.
  const Matrix6d tight = PoseCovarianceFromSigma(0.01, 0.5 * kDeg);
  const Trial t = Register(RoomCorner, Motion({0.08, -0.06, 0.06}, {0, 0.01, 0}), tight);
  EXPECT_FALSE(t.result.accepted);
  EXPECT_NE(t.result.verdict.find("inconsistent with the prior"), std::string::npos) << t.result.verdict;
  EXPECT_GT(t.result.mahalanobis2, 22.46);
  EXPECT_TRUE(t.result.covariance.isApprox(tight));  // nothing learnt: the prior's uncertainty stands
  // The same offset under a prior that allows it is corrected.
  const Trial wide = Register(RoomCorner, t.correction_true, PoseCovarianceFromSigma(0.08, 0.05));
  EXPECT_TRUE(wide.result.accepted) << wide.result.verdict;
  EXPECT_LT(Remaining(wide).head<3>().norm(), 0.01);
}

TEST(RegistrationTest, RelativeCovarianceCarriesTheLeverArmOfTheEarlierCamerasRotation) {
  // The current camera at the map origin (optical axes = map axes), the earlier 2 m along its optical axis:
  // a rotation error of the earlier camera about map x moves it, seen from the current one, by 2 m x angle in y.
  const Isometry3d X_current = Isometry3d::Identity();
  Isometry3d X_earlier = Isometry3d::Identity();
  X_earlier.translation() = Vector3d(0, 0, 2);
  Matrix6d earlier = Matrix6d::Zero();
  earlier(3, 3) = 0.01 * 0.01;
  const Matrix6d c = RelativePoseCovariance(X_current, Matrix6d::Zero(), X_earlier, earlier);
  EXPECT_NEAR(std::sqrt(c(1, 1)), 0.02, 1e-9);
  EXPECT_NEAR(std::sqrt(c(3, 3)), 0.01, 1e-9);
  EXPECT_NEAR(c(0, 0), 0.0, 1e-12);
  // The current camera's rotation turns about the current frame's origin: no lever arm.
  const Matrix6d d = RelativePoseCovariance(X_current, earlier, X_earlier, Matrix6d::Zero());
  EXPECT_NEAR(d(1, 1), 0.0, 1e-12);
  EXPECT_NEAR(std::sqrt(d(3, 3)), 0.01, 1e-9);
  // Rotated into the current camera frame: a map-x translation error of a camera looking along map +y.
  const Isometry3d X_turned(Eigen::AngleAxisd(std::numbers::pi / 2, Vector3d::UnitZ()));
  Matrix6d tx = Matrix6d::Zero();
  tx(0, 0) = 1e-4;
  const Matrix6d e = RelativePoseCovariance(X_turned, tx, X_turned, Matrix6d::Zero());
  EXPECT_NEAR(e(1, 1), 1e-4, 1e-12);  // map x is the turned camera's -y
}

TEST(RegistrationTest, NonFiniteOrTooFewPointsKeepThePrior) {
  std::vector<Eigen::Vector3f> few = {{0, 0, 1}, {0, 1, 1}};
  const IcpResult r = AlignIcp(few, few, IcpParams{});
  EXPECT_FALSE(r.accepted);
  EXPECT_TRUE(r.correction.isApprox(Isometry3d::Identity()));
  rs::Rng rng(3);
  std::vector<Eigen::Vector3f> corner;
  RoomCorner(corner, rng, 0.0);
  Matrix6d bad = kPrior;
  bad(0, 0) = std::numeric_limits<double>::quiet_NaN();
  const IcpResult n = AlignIcp(corner, PrepareIcpTarget(corner, IcpParams{}), bad);
  EXPECT_FALSE(n.accepted);
  EXPECT_TRUE(n.correction.matrix().allFinite());
}

}  // namespace
}  // namespace anchordb::engine
