// The keep rules of forgetting (engine/forgetting/keep_rules.h): each reason keeps on its own, the first reason in
// the enum's order is the one reported, and without any the old event or keyframe is forgotten.
#include "engine/forgetting/keep_rules.h"

#include <gtest/gtest.h>

namespace anchordb::engine::forgetting {
namespace forgetting_keep_rules_test {

TEST(ForgettingKeepRulesTest, AnEventStaysForEachReasonAloneAndReportsTheFirst) {
  EXPECT_EQ(KeepEvent({}), EventKeep::kForget);
  EXPECT_EQ(KeepEvent({.pinned = true}), EventKeep::kPinned);
  EXPECT_EQ(KeepEvent({.labelled = true}), EventKeep::kLabelled);
  EXPECT_EQ(KeepEvent({.instance_pinned = true}), EventKeep::kInstancePinned);
  EXPECT_EQ(KeepEvent({.latest_of_instance = true}), EventKeep::kLatestOfInstance);
  EXPECT_EQ(KeepEvent({true, true, true, true}), EventKeep::kPinned);
  EXPECT_EQ(KeepEvent({false, true, true, true}), EventKeep::kLabelled);
  EXPECT_EQ(KeepEvent({false, false, true, true}), EventKeep::kInstancePinned);
}

TEST(ForgettingKeepRulesTest, AKeyframeStaysForEachReasonAloneAndReportsTheFirst) {
  constexpr double kKeepAtLeast = 0.5;
  EXPECT_EQ(KeepKeyframe({}, kKeepAtLeast), KeyframeKeep::kForget);
  EXPECT_EQ(KeepKeyframe({.pinned = true}, kKeepAtLeast), KeyframeKeep::kPinned);
  EXPECT_EQ(KeepKeyframe({.relevance = 0.5}, kKeepAtLeast), KeyframeKeep::kRelevant);  // at the bar: kept
  EXPECT_EQ(KeepKeyframe({.relevance = 0.49}, kKeepAtLeast), KeyframeKeep::kForget);
  EXPECT_EQ(KeepKeyframe({.relevance = 0.49}, 0.4), KeyframeKeep::kRelevant);           // the policy's bar
  EXPECT_EQ(KeepKeyframe({.referenced = true}, kKeepAtLeast), KeyframeKeep::kReferenced);
  EXPECT_EQ(KeepKeyframe({.scene_open = true, .scene_fed_recently = true}, kKeepAtLeast), KeyframeKeep::kOpenScene);
  EXPECT_EQ(KeepKeyframe({true, 1.0, true, true, true}, kKeepAtLeast), KeyframeKeep::kPinned);
  EXPECT_EQ(KeepKeyframe({false, 1.0, true, true, true}, kKeepAtLeast), KeyframeKeep::kRelevant);
  EXPECT_EQ(KeepKeyframe({false, 0.0, true, true, true}, kKeepAtLeast), KeyframeKeep::kReferenced);
}

TEST(ForgettingKeepRulesTest, AnAbandonedSceneProtectsNothing) {
  // Left observing, but no frame within the keyframe age: its keyframes age like any others.
  EXPECT_EQ(KeepKeyframe({.scene_open = true, .scene_fed_recently = false}, 0.5), KeyframeKeep::kForget);
  // A closed scene's keyframes are not protected by a recent frame either.
  EXPECT_EQ(KeepKeyframe({.scene_open = false, .scene_fed_recently = true}, 0.5), KeyframeKeep::kForget);
}

}  // namespace
}  // namespace anchordb::engine::forgetting
