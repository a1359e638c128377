// Sentence building (engine/events/sentences.h): the where-is sentence with the English plural heuristic, positions
// in words and the explanations of events.
#include <gtest/gtest.h>

#include "engine/events/sentences.h"

namespace anchordb::engine {
namespace events_sentences_test {

TEST(EventsSentencesTest, PluralByTheLastLetter) {
  EXPECT_TRUE(IsPluralLabel("keys"));
  EXPECT_TRUE(IsPluralLabel("glasses"));
  EXPECT_FALSE(IsPluralLabel("mug"));
  EXPECT_FALSE(IsPluralLabel(""));
}

TEST(EventsSentencesTest, WhereSentencesNowInThePastAndAfterRemoval) {
  EXPECT_EQ(WhereSentence("keys", "on the table", true, false), "The keys are on the table.");
  EXPECT_EQ(WhereSentence("mug", "on the table", true, false), "The mug is on the table.");
  EXPECT_EQ(WhereSentence("keys", "on the shelf", true, true), "The keys were on the shelf.");
  EXPECT_EQ(WhereSentence("mug", "on the shelf", true, true), "The mug was on the shelf.");
  EXPECT_EQ(WhereSentence("keys", "on the shelf", false, true),
            "The keys were last seen on the shelf; they were taken away and have not been seen since.");
  EXPECT_EQ(WhereSentence("mug", "on the shelf", false, false),
            "The mug was last seen on the shelf; it was taken away and has not been seen since.");
}

TEST(EventsSentencesTest, PositionsInWords) {
  EXPECT_EQ(MapPositionPhrase({1.23456, -0.5, 0.8}), "at (1.234, -0.50) in the map");
  EXPECT_EQ(PositionText({1.0, -0.256, 12.3456}), "(1.00, -0.26, 12.35)");
  EXPECT_EQ(FixedDigits(0.456), "0.46");
  EXPECT_EQ(FixedDigits(2.0, 3), "2.000");
}

TEST(EventsSentencesTest, EventExplanations) {
  EXPECT_EQ(MoveExplanation("keys", 7, {0, 3, 0.9}, {2.3, 0.1, 0.8}, 0.912),
            "inferred move (lost-key rule, thesis 3.3.4): 'keys' (instance 7) was removed from (0.00, 3.00, 0.90) and has "
            "not been seen since; this object was added at (2.30, 0.10, 0.80) by an observed action, without a new label, "
            "and is of compatible size (similarity 0.91)");
  EXPECT_NE(AddedExplanation(Detection::kMeanwhile).find("while the robot was away"), std::string::npos);
  EXPECT_NE(AddedExplanation(Detection::kObserved).find("added while observing"), std::string::npos);
  EXPECT_EQ(ReanalysisRemovedExplanation(4), "the background of scene 4 lies behind where this object stood: it is gone");
  EXPECT_EQ(ReanalysisAddedExplanation(3, 4).rfind("keyframe 3 re-analysed with the background of scene 4", 0), 0u);
  EXPECT_NE(LabelledExplanation(true).find("operator"), std::string::npos);
  EXPECT_EQ(LabelledExplanation(false), "a person named the object in dialog");
}

}  // namespace
}  // namespace anchordb::engine
