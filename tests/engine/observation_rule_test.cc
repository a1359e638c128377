#include "engine/observation/observation_rule.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace anchordb::engine {
namespace observation_rule_test {

Eigen::Isometry3d PoseAt(double x_m, double yaw_rad = 0.0) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X.translation() = Eigen::Vector3d(x_m, 0.0, 1.0);
  return X;
}

struct Trace {
  std::vector<ObservationStep> steps;
  int opens = 0;
  int fed = 0;
};

// Offers frames at rate_hz from t0_s for duration_s, the pose given by pose_of(t).
template <typename PoseOf>
void Offer(ObservationRule& rule, Trace& trace, double t0_s, double duration_s, double rate_hz, PoseOf pose_of) {
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  for (int i = 0; i < n; ++i) {
    const double t_s = t0_s + i / rate_hz;
    const ObservationStep step = rule.OnFrame(t_s, pose_of(t_s));
    trace.opens += step.open ? 1 : 0;
    trace.fed += step.feed ? 1 : 0;
    trace.steps.push_back(step);
  }
}

TEST(ObservationRuleTest, OpensAfterDwellAndFeedsWhileStill) {
  ObservationRule rule;  // defaults: dwell 1.0 s, window 0.5 s
  Trace trace;
  Offer(rule, trace, 0.0, 3.0, 10.0, [](double) { return PoseAt(1.0); });
  ASSERT_EQ(trace.opens, 1);
  // The first frame starts the still run; the model opens at t = 1.0 s (frame 10) and takes frames 10..29.
  EXPECT_TRUE(trace.steps[10].open);
  EXPECT_FALSE(trace.steps[9].feed);
  EXPECT_EQ(trace.fed, 20);
  EXPECT_EQ(rule.counts().moving, 10);
  EXPECT_EQ(rule.Finish(), ObservationCloseReason::kEndOfStream);
  EXPECT_EQ(rule.counts().closed_end, 1);
  EXPECT_EQ(rule.Finish(), ObservationCloseReason::kNone);
}

TEST(ObservationRuleTest, MovingCameraOpensNothing) {
  ObservationRule rule;
  Trace trace;
  // 0.3 m/s: 3 cm per frame at 10 Hz, so the window's oldest pose is always beyond 3 cm.
  Offer(rule, trace, 0.0, 5.0, 10.0, [](double t_s) { return PoseAt(0.3 * t_s); });
  EXPECT_EQ(trace.opens, 0);
  EXPECT_EQ(rule.counts().moving, 50);
  // Turning in place at 0.5 rad/s is movement too.
  Offer(rule, trace, 10.0, 5.0, 10.0, [](double t_s) { return PoseAt(0.0, 0.5 * t_s); });
  EXPECT_EQ(trace.opens, 0);
}

TEST(ObservationRuleTest, TwoVisitsWithADriveBetween) {
  ObservationRule rule;
  Trace trace;
  Offer(rule, trace, 0.0, 3.0, 10.0, [](double) { return PoseAt(0.0); });                // pause at the table
  Offer(rule, trace, 3.0, 4.0, 10.0, [](double t_s) { return PoseAt(0.5 * (t_s - 3.0)); });  // drive 2 m away
  Offer(rule, trace, 7.0, 3.0, 10.0, [](double) { return PoseAt(2.0); });                // pause elsewhere
  Offer(rule, trace, 10.0, 4.0, 10.0, [](double t_s) { return PoseAt(2.0 - 0.5 * (t_s - 10.0)); });  // back
  Offer(rule, trace, 14.0, 3.0, 10.0, [](double) { return PoseAt(0.0); });               // second visit
  EXPECT_EQ(trace.opens, 3);
  EXPECT_EQ(rule.counts().closed_left, 2);
  ASSERT_TRUE(rule.X_MapAnchor().has_value());
  EXPECT_NEAR(rule.X_MapAnchor()->translation().x(), 0.0, 1e-9);
  // The close comes with the first frame of the drive beyond 0.15 m (t = 3.4 s: 0.2 m), which is not fed.
  const ObservationStep& leaving = trace.steps[34];
  EXPECT_EQ(leaving.close_reason, ObservationCloseReason::kCameraLeft);
  EXPECT_FALSE(leaving.feed);
  EXPECT_TRUE(trace.steps[33].feed);
}

TEST(ObservationRuleTest, SensorNoiseBelowThresholdsKeepsTheModelOpen) {
  ObservationRule rule;
  std::mt19937 rng(32);  // seeded: the same jitter on every run
  std::normal_distribution<double> jitter_m(0.0, 0.004);
  std::normal_distribution<double> jitter_rad(0.0, 0.004);
  Trace trace;
  Offer(rule, trace, 0.0, 10.0, 30.0, [&](double) { return PoseAt(1.0 + jitter_m(rng), jitter_rad(rng)); });
  EXPECT_EQ(trace.opens, 1);
  EXPECT_EQ(rule.counts().closed_left, 0);
  EXPECT_GE(trace.fed, 265);  // all but the first second's 30 frames (and a few of noise's outliers)
}

TEST(ObservationRuleTest, TimeGapClosesAndDwellStartsAgain) {
  ObservationRule rule;
  Trace trace;
  Offer(rule, trace, 0.0, 2.0, 10.0, [](double) { return PoseAt(0.0); });
  ASSERT_TRUE(rule.model_open());
  // 5 s without frames, then the same place again: the gap closes the model, a new one opens after a new dwell.
  const ObservationStep after_gap = rule.OnFrame(6.9, PoseAt(0.0));
  EXPECT_EQ(after_gap.close_reason, ObservationCloseReason::kTimeGap);
  EXPECT_FALSE(after_gap.open);
  EXPECT_FALSE(after_gap.feed);
  Offer(rule, trace, 7.0, 2.0, 10.0, [](double) { return PoseAt(0.0); });
  EXPECT_EQ(rule.counts().opened, 2);
  EXPECT_EQ(rule.counts().closed_gap, 1);
}

TEST(ObservationRuleTest, StampsThatDoNotAdvanceAreIgnored) {
  ObservationRule rule;
  Trace trace;
  Offer(rule, trace, 0.0, 2.0, 10.0, [](double) { return PoseAt(0.0); });
  const ObservationRuleCounts before = rule.counts();
  const ObservationStep repeat = rule.OnFrame(1.9, PoseAt(5.0));
  EXPECT_TRUE(repeat.ignored);
  EXPECT_FALSE(repeat.feed);
  EXPECT_EQ(repeat.close_reason, ObservationCloseReason::kNone);
  EXPECT_TRUE(rule.OnFrame(1.5, PoseAt(0.0)).ignored);
  EXPECT_TRUE(rule.OnFrame(std::nan(""), PoseAt(0.0)).ignored);
  EXPECT_EQ(rule.counts().ignored, 3);
  EXPECT_EQ(rule.counts().fed, before.fed);
  EXPECT_TRUE(rule.model_open());
}

TEST(ObservationRuleTest, ZeroDwellOpensOnTheFirstStillFrame) {
  ObservationRuleParams params;
  params.min_dwell_s = 0.0;
  ObservationRule rule(params);
  EXPECT_TRUE(rule.OnFrame(0.0, PoseAt(0.0)).open);
}

TEST(ObservationRuleTest, BadSettingsAreRejectedByName) {
  ObservationRuleParams params;
  params.still_window_s = 0.0;
  EXPECT_THROW(ObservationRule{params}, std::invalid_argument);
  params = {};
  params.min_dwell_s = -1.0;
  EXPECT_THROW(ValidateObservationRuleParams(params), std::invalid_argument);
  params = {};
  params.leave_translation_m = 0.01;  // below still_translation_m 0.03: a model would close while still
  try {
    ValidateObservationRuleParams(params);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("leave_translation_m"), std::string::npos);
  }
  EXPECT_EQ(ObservationCloseReasonName(ObservationCloseReason::kTimeGap), "time_gap");
}

TEST(ObservationRuleTest, PoseDistanceAndAngle) {
  EXPECT_NEAR(PoseDistanceM(PoseAt(0.0), PoseAt(0.25)), 0.25, 1e-12);
  EXPECT_NEAR(PoseAngleRad(PoseAt(0.0, 0.1), PoseAt(0.0, -0.2)), 0.3, 1e-9);
  EXPECT_NEAR(PoseAngleRad(PoseAt(0.0), PoseAt(0.0)), 0.0, 1e-6);
}

}  // namespace
}  // namespace anchordb::engine
