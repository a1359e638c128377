// The backlog thresholds of keyframe analyses (engine/events/analysis_backlog.h).
#include <gtest/gtest.h>

#include "engine/events/analysis_backlog.h"

namespace anchordb::engine {
namespace events_analysis_backlog_test {

TEST(AnalysisBacklogTest, FramesAreRefusedFromTheBoundOnAndCatchUpStartsAtItsThreshold) {
  const AnalysisBacklogLimits limits{4, 10};
  EXPECT_FALSE(RefusesFrames(limits, 0));
  EXPECT_FALSE(RefusesFrames(limits, 9));
  EXPECT_TRUE(RefusesFrames(limits, 10));
  EXPECT_TRUE(RefusesFrames(limits, 11));
  EXPECT_FALSE(NeedsCatchUp(limits, 3));
  EXPECT_TRUE(NeedsCatchUp(limits, 4));
  EXPECT_TRUE(NeedsCatchUp(limits, 10));
}

TEST(AnalysisBacklogTest, ZeroTurnsEitherOff) {
  EXPECT_FALSE(RefusesFrames({4, 0}, 1000000));
  EXPECT_TRUE(NeedsCatchUp({4, 0}, 4));
  EXPECT_FALSE(NeedsCatchUp({0, 10}, 1000000));
  EXPECT_TRUE(RefusesFrames({0, 10}, 10));
}

}  // namespace
}  // namespace anchordb::engine
