// Sequences of descriptions (thesis 5.3.3-5.3.4): a reversion to a hypothesis that was not the best (figures
// 5.8-5.10), one assessment scheme per sequence (figure 5.11), determinism.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "engine/grounding/grounding.h"
#include "engine/grounding/parser.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace grounding_sequence_test {

constexpr int kChair = 0, kPlant = 1, kShelf = 2;

Knowledge ThreeCategoryKnowledge() {
  Knowledge k;
  k.categories = CategoryTable({{"chair", "chair", Nature::kVehicle, {"chair"}},
                                {"plant", "plant", Nature::kNone, {"plant"}},
                                {"shelf", "shelf", Nature::kOpposite, {"shelf"}}});
  const double p_int[3] = {0.1, 0.4, 0.1};  // a listener who expects few intrinsic descriptions of chairs
  for (int n = 0; n < kNatureCount; ++n) {
    for (int o = 0; o < kOrientationCount; ++o) {
      for (int r = 0; r < kRelationCount; ++r) {
        k.prior.SetIntrinsic(Scheme::kStatistical, static_cast<Nature>(n), static_cast<Orientation>(o),
                             static_cast<Relation>(r), p_int[n]);
      }
    }
  }
  return k;
}

// The chair v0 faces the viewer's right; the plant v1 stands to its left (relative), i.e. behind it; the shelf v2
// stands in front of it (relative), i.e. to its right.
FurnitureGraph ThreePieceGraph() {
  FurnitureGraph g;
  g.category_count = 3;
  g.vertices = {{"v0", {}, {}, 0.0}, {"v1", {}, {}, 0.0}, {"v2", {}, {}, 0.0}};
  g.edges = {Edge{0, 1, 0.5, {Distribution4{0.1, 0.7, 0.1, 0.1}, Distribution4{0.7, 0.1, 0.1, 0.1}}},
             Edge{0, 2, 0.5, {Distribution4{0.05, 0.05, 0.05, 0.85}, Distribution4{0.05, 0.05, 0.85, 0.05}}},
             Edge{1, 2, 1.2, {Distribution4{0.2, 0.1, 0.6, 0.1}, Distribution4{0.1, 0.2, 0.1, 0.6}}}};
  g.initial.category = {0.6, 0.1, 0.3, 0.2, 0.7, 0.1, 0.55, 0.05, 0.4};
  g.initial.orientation.assign(12, 0.25);
  for (const Edge& e : g.edges) {
    for (const Distribution4& p : e.visual) g.initial.relation.insert(g.initial.relation.end(), p.begin(), p.end());
  }
  return g;
}

TEST(GroundingSequenceTest, ALaterDescriptionRevertsToAnEarlierLowerRankedHypothesis) {
  const Knowledge k = ThreeCategoryKnowledge();
  const FurnitureGraph g = ThreePieceGraph();
  GroundingParams params;
  params.n_best = 20;
  params.sigma = 2.0;
  params.schemes = {Scheme::kStatistical};
  // 1: "the plant is behind the chair". Best: the relative reading on the plant-chair edge, (1.3 + 0.1 x 0.9 x
  // 0.25) / 3 = 0.43917; second: the intrinsic reading with the chair's front to the right, (1.3 + 0.7 x 0.1 x 0.25)
  // / 3 = 0.43750, which also learns p(o | chair) = (0.175, 0.475, 0.175, 0.175) by eq. 5.5.
  const HypothesisSet s1 = Ground(g, k, InitialHypotheses(g), {kPlant, Relation::kBehind, kChair}, params);
  ASSERT_EQ(s1.ranked[0].matches[0].interpretation, 0);
  ASSERT_EQ(s1.ranked[1].matches[0].interpretation, 1 + static_cast<int>(Orientation::kRight));
  EXPECT_EQ(s1.ranked[0].matches[0].directed_edge, 1);
  // 2: "the shelf is to the right of the chair": only an intrinsic reading with the front to the right fits the
  // geometry (the shelf is in front of the chair as seen). On G1 (uniform p(o)) it scores (0.4 + 0.8 + 0.85 x 0.1 x
  // 0.25) / 3; on G2 (p(right) = 0.475) (1.2 + 0.85 x 0.1 x 0.475) / 3: the gain (0.01913 / 3) exceeds the lead of
  // G1 (0.005 / 3), so the best sequence now starts with the match that was second after description 1.
  const HypothesisSet s2 = Ground(g, k, s1, {kShelf, Relation::kRightOf, kChair}, params);
  const Hypothesis& best = s2.ranked[0];
  EXPECT_EQ(best.parent_id, s1.ranked[1].id);
  EXPECT_EQ(best.lineage_ranks, (std::vector<int>{1, 0}));
  EXPECT_EQ(best.lineage, (std::vector<std::int64_t>{s1.ranked[1].id, best.id}));
  EXPECT_NEAR(best.score, (1.3 + 0.7 * 0.1 * 0.25) / 3.0 + (1.2 + 0.85 * 0.1 * 0.475) / 3.0, 1e-12);
  EXPECT_EQ(best.matches[1].directed_edge, 3);
  EXPECT_EQ(best.matches[1].relative, Relation::kInFrontOf);
  // The previously preferred sequence is not discontinued: it lives on lower in the list (figure 5.10).
  bool g1_alive = false;
  for (const Hypothesis& h : s2.ranked) g1_alive = g1_alive || h.parent_id == s1.ranked[0].id;
  EXPECT_TRUE(g1_alive);
  // The chair's orientation is now believed to point right, as the geometry and both descriptions imply.
  const double* p_o = &best.state.orientation[0];
  EXPECT_GT(p_o[static_cast<int>(Orientation::kRight)], 0.6);
}

// Six pieces of the default categories, aligned with the view.
FurnitureGraph LivingRoom(const Knowledge& k) {
  Viewpoint view{{0.0, 0.0}, 0.0};  // looking along map +x; map +y is the viewer's left
  const auto pf = [&](const char* id) {
    std::vector<double> p(static_cast<std::size_t>(k.categories.size()), 0.3 / (k.categories.size() - 1));
    p[static_cast<std::size_t>(k.categories.IndexOfId(id))] = 0.7;
    return p;
  };
  std::vector<FurnitureInput> f = {{"sofa", {4.0, 0.0}, {0.9, 2.0}, 0.0, pf("sofa")},
                                   {"plant", {4.0, 1.7}, {0.4, 0.4}, 0.0, pf("plant")},
                                   {"table", {2.8, 0.0}, {0.6, 1.0}, 0.0, pf("table")},
                                   {"armchair", {2.8, -1.5}, {0.8, 0.8}, 0.0, pf("armchair")},
                                   {"shelf", {4.2, -1.6}, {0.4, 1.0}, 0.0, pf("shelf")},
                                   {"stool", {2.8, 1.5}, {0.4, 0.4}, 0.0, pf("stool")}};
  return BuildFurnitureGraph(view, f, k.categories.size(), GraphParams{});
}

TEST(GroundingSequenceTest, EverySequenceKeepsOneAssessmentScheme) {
  const Knowledge& k = DefaultKnowledge();
  const FurnitureGraph g = LivingRoom(k);
  GroundingParams params;
  params.n_best = 300;
  const char* sentences[] = {"the plant is left of the sofa", "the table is in front of the sofa",
                             "the armchair is to the right of the table", "behind the armchair is the shelf",
                             "the stool is left of the table", "the sofa is behind the table",
                             "the shelf is right of the sofa", "the table is right of the stool"};
  HypothesisSet set = InitialHypotheses(g);
  std::map<std::int64_t, Scheme> scheme_of;
  for (const char* text : sentences) {
    const HypothesisSet next = Ground(g, k, set, ParseSentence(text, k.categories).description, params);
    std::set<Scheme> present;
    for (const Hypothesis& h : next.ranked) {
      ASSERT_TRUE(h.scheme.has_value());
      present.insert(*h.scheme);
      for (const Match& m : h.matches) EXPECT_EQ(m.scheme, *h.scheme) << text;
      if (set.step > 0) {
        EXPECT_EQ(scheme_of.at(h.parent_id), *h.scheme) << text;
      }
      scheme_of[h.id] = *h.scheme;
    }
    if (set.step == 0) {
      EXPECT_EQ(present.size(), 3u) << "G0 is expanded under all three schemes";
    }
    set = next;
  }
  EXPECT_EQ(set.step, 8);
  // Relative descriptions that all fit the geometry: the best sequence matched every one to its true edge.
  const Hypothesis& best = set.ranked[0];
  const int expected[][2] = {{1, 0}, {2, 0}, {3, 2}, {4, 3}, {5, 2}, {0, 2}, {4, 0}, {2, 5}};
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(best.matches[i].directed_edge, g.FindDirected(expected[i][0], expected[i][1])) << sentences[i];
  }
}

TEST(GroundingSequenceTest, GroundingIsDeterministic) {
  const Knowledge& k = DefaultKnowledge();
  const FurnitureGraph g = LivingRoom(k);
  GroundingParams params;
  params.n_best = 50;
  const auto run = [&] {
    HypothesisSet set = InitialHypotheses(g);
    for (const char* text : {"the plant is behind the sofa", "the table is in front of the sofa", "the stool is left of the table"}) {
      set = Ground(g, k, set, ParseSentence(text, k.categories).description, params);
    }
    return set;
  };
  const HypothesisSet a = run(), b = run();
  ASSERT_EQ(a.ranked.size(), b.ranked.size());
  for (std::size_t i = 0; i < a.ranked.size(); ++i) {
    EXPECT_EQ(a.ranked[i].id, b.ranked[i].id);
    EXPECT_EQ(a.ranked[i].score, b.ranked[i].score);
    EXPECT_EQ(a.ranked[i].state, b.ranked[i].state);
  }
}

TEST(GroundingSequenceTest, SpeechProductionUsesTheListenersRelationAndLabels) {
  const Knowledge& k = DefaultKnowledge();
  const FurnitureGraph g = LivingRoom(k);
  GroundingParams params;
  params.n_best = 50;
  HypothesisSet set = InitialHypotheses(g);
  // The listener calls the plant a flower and says it is left of the sofa.
  set = Ground(g, k, set, ParseSentence("the flower is left of the couch", k.categories).description, params);
  const Production p = Produce(g, k, set.ranked[0], 1, 0);
  EXPECT_EQ(k.categories[p.located_category].id, "plant");
  EXPECT_EQ(k.categories[p.reference_category].id, "sofa");
  EXPECT_EQ(p.relation, Relation::kLeftOf);
  EXPECT_EQ(p.frame, Frame::kRelative);
  double sum = 0.0;
  for (double w : p.word_probability) sum += w;
  EXPECT_NEAR(sum, 1.0, 1e-9);
  EXPECT_THROW(Produce(g, k, set.ranked[0], 1, 3), Error);  // plant and armchair share no edge
}

}  // namespace
}  // namespace anchordb::engine::grounding
