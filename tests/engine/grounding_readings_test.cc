// The readings of a hypothesis (engine/grounding/readings.h): labels, the known front, revisions, the schemes a
// graph tries, the order of alternative words and the sentences.
#include "engine/grounding/readings.h"

#include <gtest/gtest.h>

namespace anchordb::engine::grounding {
namespace grounding_readings_test {

TEST(GroundingReadings, LabelIsTheFirstMostProbableCategory) {
  GraphState s;
  s.category = {0.2, 0.5, 0.3, /* vertex 1 */ 0.4, 0.2, 0.4};
  EXPECT_EQ(MostProbableCategory(s, 3, 0), 1);
  EXPECT_EQ(MostProbableCategory(s, 3, 1), 0);  // a tie: the first
}

TEST(GroundingReadings, FrontIsKnownOnlyWhenOneOrientationStandsOut) {
  GraphState s;
  s.orientation = {0.25, 0.25, 0.25, 0.25, /* vertex 1 */ 0.1, 0.2, 0.6, 0.1, /* vertex 2 */ 0.4, 0.4, 0.1, 0.1};
  EXPECT_FALSE(KnownFront(s, 0));
  EXPECT_EQ(KnownFront(s, 1), Orientation::kFront);
  EXPECT_FALSE(KnownFront(s, 2));
}

TEST(GroundingReadings, RevisedWhenAnEarlierAncestorWasNotTheBest) {
  Hypothesis h;
  EXPECT_FALSE(IsRevised(h));
  h.lineage_ranks = {0, 0, 3};  // the last step's own rank does not count
  EXPECT_FALSE(IsRevised(h));
  h.lineage_ranks = {0, 2, 0};
  EXPECT_TRUE(IsRevised(h));
}

TEST(GroundingReadings, SchemesFromAdaptationAndThePrior) {
  EXPECT_EQ(SchemesToTry(true, false), (std::vector<Scheme>{Scheme::kStatistical, Scheme::kRelative, Scheme::kIntrinsic}));
  EXPECT_EQ(SchemesToTry(true, true), (std::vector<Scheme>{Scheme::kUniform, Scheme::kRelative, Scheme::kIntrinsic}));
  EXPECT_EQ(SchemesToTry(false, false), std::vector<Scheme>{Scheme::kStatistical});
  EXPECT_EQ(SchemesToTry(false, true), std::vector<Scheme>{Scheme::kUniform});
}

TEST(GroundingReadings, WordsByFallingProbabilityTiesInRelationOrder) {
  const auto order = WordsByProbability({0.1, 0.4, 0.1, 0.4});
  EXPECT_EQ(order, (std::array<Relation, 4>{Relation::kRightOf, Relation::kBehind, Relation::kLeftOf, Relation::kInFrontOf}));
}

TEST(GroundingReadings, Sentences) {
  EXPECT_EQ(ProductionSentence("shelf", Relation::kRightOf, "sofa"), "the shelf is to the right of the sofa");
  EXPECT_EQ(PlacementPhrase(std::nullopt, "table"), "on the table");
  EXPECT_EQ(PlacementPhrase(Relation::kBehind, "chest of drawers"), "behind the chest of drawers");
  EXPECT_EQ(PlacementPhrase(Relation::kInFrontOf, "sofa"), "in front of the sofa");
}

}  // namespace
}  // namespace anchordb::engine::grounding
