// Which newer model re-analysis of an old keyframe applies (engine/events/rules.h, ChooseReanalysisModel).
#include "engine/events/rules.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace events_reanalysis_test {

TEST(EventsReanalysisTest, TheNearestNewerModelWithFramesThatWasNotForgotten) {
  const std::vector<ReanalysisCandidate> nearest_first = {
      {4, 30, false},  // the keyframe's own model
      {2, 30, false},  // older
      {8, 0, false},   // newer, but it took no frame
      {9, 12, true},   // newer, its state forgotten
      {11, 5, false},  // this one
      {12, 40, false}};
  EXPECT_EQ(ChooseReanalysisModel(4, nearest_first), 11);
  EXPECT_EQ(ChooseReanalysisModel(12, nearest_first), std::nullopt);
  EXPECT_EQ(ChooseReanalysisModel(4, {}), std::nullopt);
}

}  // namespace
}  // namespace anchordb::engine
