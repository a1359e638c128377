// The where-is rules (engine/events/where.h): which instance a label means, how the position is known and the
// confidence (0.95 observed, 0.85 meanwhile, 0.7 inferred, 0.8 otherwise), and plain-geometry placement words.
#include <gtest/gtest.h>

#include "engine/events/where.h"

namespace anchordb::engine {
namespace events_where_test {

TEST(EventsWhereTest, ConfidenceByHowThePositionIsKnown) {
  EXPECT_EQ(PositionConfidence("observed"), 0.95);
  EXPECT_EQ(PositionConfidence("meanwhile"), 0.85);
  EXPECT_EQ(PositionConfidence("inferred"), 0.7);
  EXPECT_EQ(PositionConfidence("reanalysis"), 0.8);
  EXPECT_EQ(PositionConfidence("operator"), 0.8);
  EXPECT_DOUBLE_EQ(WhereConfidence(0.5, "inferred"), 0.35);
  EXPECT_EQ(HowKnown(std::nullopt), "observed");
  EXPECT_EQ(HowKnown(PositionOrigin{"moved", "observed"}), "inferred");
  EXPECT_EQ(HowKnown(PositionOrigin{"added", "meanwhile"}), "meanwhile");
  EXPECT_EQ(HowKnown(PositionOrigin{"removed", "observed"}), "observed");
}

TEST(EventsWhereTest, TheMostLikelyInstanceAndAmongEqualsTheMostRecentPosition) {
  EXPECT_EQ(ChooseWhereCandidate({}), -1);
  EXPECT_EQ(ChooseWhereCandidate({{0.0, 5}, {0.5, std::nullopt}}), -1);  // not this label, or not known then
  EXPECT_EQ(ChooseWhereCandidate({{0.4, 9}, {0.6, 1}, {0.5, 10}}), 1);
  EXPECT_EQ(ChooseWhereCandidate({{0.5, 3}, {0.5 + 1e-12, 7}, {0.5, 5}}), 1);  // equal within 1e-9: newest
  EXPECT_EQ(ChooseWhereCandidate({{0.5, 7}, {0.5, 7}}), 0);                    // a tie keeps the first
}

TEST(EventsWhereTest, PlacementWordsOnOrRelativeToThePiece) {
  Placement on;
  on.piece = 0;
  on.on = true;
  EXPECT_EQ(DescribePlacement(on, "table").relation, "on");
  EXPECT_EQ(DescribePlacement(on, "table").phrase, "on the table");
  Placement left;
  left.piece = 0;
  left.relative = grounding::Relation::kLeftOf;
  const PlacementWords w = DescribePlacement(left, "shelf");
  EXPECT_EQ(w.relation, grounding::RelationId(grounding::Relation::kLeftOf));
  EXPECT_EQ(w.phrase, std::string(grounding::RelationPhrase(grounding::Relation::kLeftOf)) + " the shelf");
}

}  // namespace
}  // namespace anchordb::engine
