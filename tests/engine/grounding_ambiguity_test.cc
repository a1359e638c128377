// Ambiguity as an answer of grounding (issue 17): a description two pieces fit about equally well is held (no
// category moves) until a later description or an explicit resolution settles it; a poor match moves no category
// until a second description confirms it.
#include <gtest/gtest.h>

#include "engine/grounding/ambiguity.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace grounding_ambiguity_test {

int Cat(const char* id) { return DefaultKnowledge().categories.IndexOfId(id); }

std::vector<double> Pf(std::initializer_list<std::pair<const char*, double>> weights) {
  std::vector<double> p(static_cast<std::size_t>(DefaultKnowledge().categories.size()), 0.0);
  for (const auto& [id, w] : weights) p[static_cast<std::size_t>(Cat(id))] = w;
  return p;
}

// Seen from the origin along +x (+y = the viewer's left): a chair, a table to its left, a table in front of it,
// a plant behind it (the scene of tests/http/grounding_ambiguity_http_test.cc).
FurnitureGraph TwoTables() {
  return BuildFurnitureGraph({{0, 0}, 0},
                             {{"chair", {3.0, 0.0}, {0.5, 0.5}, 0, Pf({{"chair", 0.7}, {"armchair", 0.2}, {"stool", 0.1}})},
                              {"table_left", {3.0, 1.3}, {0.8, 0.8}, 0, Pf({{"table", 0.7}, {"stool", 0.2}, {"chair", 0.1}})},
                              {"table_front", {1.9, 0.0}, {0.6, 0.6}, 0, Pf({{"table", 0.7}, {"stool", 0.2}, {"chair", 0.1}})},
                              {"plant", {4.1, 0.0}, {0.4, 0.4}, 0, Pf({{"plant", 0.9}, {"stool", 0.1}})}},
                             DefaultKnowledge().categories.size(), {});
}

const GroundingParams& Issue17Params() {
  static const GroundingParams kParams = [] {
    GroundingParams p;
    p.ambiguity_margin = 0.02;
    p.category_floor = 0.05;
    return p;
  }();
  return kParams;
}

bool CategoriesAsSeen(const FurnitureGraph& g, const HypothesisSet& set) {
  return std::all_of(set.ranked.begin(), set.ranked.end(), [&](const Hypothesis& h) { return h.state.category == g.initial.category; });
}

TEST(GroundingAmbiguityTest, HeldUntilALaterDescriptionSettlesIt) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), {Cat("table"), Relation::kLeftOf, Cat("chair")}, Issue17Params());
  ASSERT_EQ(set.held.size(), 1u);
  EXPECT_EQ(set.held[0].step, 0);
  const auto alternatives = AlternativesAt(g, set, 0, 0.02, 3);
  ASSERT_GE(alternatives.size(), 2u);
  EXPECT_NE(alternatives[0].located, alternatives[1].located);
  EXPECT_TRUE(CategoriesAsSeen(g, set));
  // Without the margin the same description is not held and moves the categories (the thesis).
  const GroundingParams thesis;
  EXPECT_TRUE(Ground(g, k, InitialHypotheses(g), {Cat("table"), Relation::kLeftOf, Cat("chair")}, thesis).held.empty());

  // A relative-frame speaker goes on: the table in front of the chair. Only one reading of description 1 stays near.
  // Next: the table is in front of the chair. Read with the chair's front to the viewer's left, both descriptions
  // are intrinsic and fit one table each; that reading now leads every other by more than the margin, so
  // description 1 settles and its held category update applies in every hypothesis.
  set = Ground(g, k, set, {Cat("table"), Relation::kInFrontOf, Cat("chair")}, Issue17Params());
  EXPECT_TRUE(set.held.empty());
  EXPECT_EQ(AlternativesAt(g, set, 0, 0.02, 3).size(), 1u);
  const int table_front = g.VertexIndex("table_front");
  const Hypothesis& best = set.ranked.front();
  EXPECT_EQ(g.Located(best.matches[0].directed_edge), table_front);
  const std::size_t kk = static_cast<std::size_t>(g.category_count);
  EXPECT_GT(best.state.category[static_cast<std::size_t>(table_front) * kk + static_cast<std::size_t>(Cat("table"))], 0.75);
}

TEST(GroundingAmbiguityTest, ResolutionKeepsTheNamedReadingAndRefusesOthersWithoutChange) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const Description d{Cat("table"), Relation::kLeftOf, Cat("chair")};
  const HypothesisSet held = Ground(g, k, InitialHypotheses(g), d, Issue17Params());
  ASSERT_EQ(held.held.size(), 1u);
  const int chair = g.VertexIndex("chair"), front = g.VertexIndex("table_front"), plant = g.VertexIndex("plant");
  HypothesisSet copy = held;
  EXPECT_THROW(KeepPair(g, copy, 1, front, chair, 3.0, 0.05), Error);         // not a held step
  EXPECT_THROW(KeepPair(g, copy, 0, plant, front, 3.0, 0.05), Error);         // no reading, or a poor one
  EXPECT_EQ(copy.ranked.size(), held.ranked.size());
  EXPECT_EQ(copy.held.size(), 1u);
  KeepPair(g, copy, 0, front, chair, 3.0, 0.05);
  EXPECT_TRUE(copy.held.empty());
  for (const Hypothesis& h : copy.ranked) EXPECT_EQ(g.Located(h.matches[0].directed_edge), front);
  EXPECT_FALSE(CategoriesAsSeen(g, copy));
}

TEST(GroundingAmbiguityTest, APoorMatchMovesNoCategoryUntilASecondDescriptionConfirmsIt) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const Description d{Cat("cupboard"), Relation::kBehind, Cat("chair")};  // nothing is believed to be a cupboard
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, Issue17Params());
  EXPECT_TRUE(set.held.empty());  // poor, not ambiguous
  EXPECT_TRUE(IsPoorMatch(g, set.ranked.front().state, d, set.ranked.front().matches.back(), 0.05));
  EXPECT_TRUE(CategoriesAsSeen(g, set));
  // Said again of the same piece: confirmed, the categories move.
  set = Ground(g, k, set, d, Issue17Params());
  EXPECT_FALSE(CategoriesAsSeen(g, set));
}

}  // namespace
}  // namespace anchordb::engine::grounding
