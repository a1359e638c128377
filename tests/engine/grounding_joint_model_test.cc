// The joint model of grounding (engine/grounding/joint_model.h): the speaker's frame preference as a Beta-Bernoulli
// posterior, the naming noise, the proximity of the pieces, the line-of-sight relative frame, scores as
// log-likelihoods, and the rules every model keeps (a poor match moves no category; an ambiguous step is held).
#include <gtest/gtest.h>

#include <cmath>

// GCC 12 at -O2 reports the default schemes of GroundingParams (an initializer list) as maybe uninitialized when
// their copy is inlined into a test body: a false positive (the same code compiles cleanly elsewhere).
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "engine/grounding/ambiguity.h"
#include "engine/grounding/joint_model.h"

namespace anchordb::engine::grounding {
namespace grounding_joint_model_test {

int Cat(const char* id) { return DefaultKnowledge().categories.IndexOfId(id); }

std::vector<double> Pf(std::initializer_list<std::pair<const char*, double>> weights) {
  std::vector<double> p(static_cast<std::size_t>(DefaultKnowledge().categories.size()), 0.0);
  for (const auto& [id, w] : weights) p[static_cast<std::size_t>(Cat(id))] = w;
  return p;
}

double P(const FurnitureGraph& g, const GraphState& s, const char* vertex, const char* category) {
  return s.category[static_cast<std::size_t>(g.VertexIndex(vertex) * g.category_count + Cat(category))];
}

GroundingParams Joint(double line_of_sight_weight = 0.5) {
  GroundingParams p;
  p.model = Model::kJoint;
  p.category_floor = 0.05;
  p.joint.line_of_sight_weight = line_of_sight_weight;
  return p;
}

// Seen from the origin along +x (+y = the viewer's left): a chair, a table to its left, a table in front of it,
// a plant behind it (the scene of tests/engine/grounding_ambiguity_test.cc).
FurnitureGraph TwoTables() {
  return BuildFurnitureGraph({{0, 0}, 0},
                             {{"chair", {3.0, 0.0}, {0.5, 0.5}, 0, Pf({{"chair", 0.7}, {"armchair", 0.2}, {"stool", 0.1}})},
                              {"table_left", {3.0, 1.3}, {0.8, 0.8}, 0, Pf({{"table", 0.7}, {"stool", 0.2}, {"chair", 0.1}})},
                              {"table_front", {1.9, 0.0}, {0.6, 0.6}, 0, Pf({{"table", 0.7}, {"stool", 0.2}, {"chair", 0.1}})},
                              {"plant", {4.1, 0.0}, {0.4, 0.4}, 0, Pf({{"plant", 0.9}, {"stool", 0.1}})}},
                             DefaultKnowledge().categories.size(), {});
}

TEST(GroundingJointModelTest, TheSpeakersFramePreferenceIsABetaBernoulliPosterior) {
  EXPECT_DOUBLE_EQ(IntrinsicPreference(0.4, {0, 0}, 5.0), 0.4);
  EXPECT_DOUBLE_EQ(IntrinsicPreference(0.4, {0, 10}, 5.0), 2.0 / 15.0);   // ten relative readings
  EXPECT_DOUBLE_EQ(IntrinsicPreference(0.4, {10, 10}, 5.0), 12.0 / 15.0);  // ten intrinsic ones
  // Only readings of references with a front count: a plant has none.
  const Knowledge& k = DefaultKnowledge();
  Match on_chair, on_plant;
  on_chair.interpretation = 1;  // intrinsic
  on_chair.reference_category = Cat("chair");
  on_plant.interpretation = 0;
  on_plant.reference_category = Cat("plant");
  const FrameCounts c = CountFrames(k, {on_chair, on_plant, on_chair});
  EXPECT_EQ(c.intrinsic, 2);
  EXPECT_EQ(c.total, 2);
}

TEST(GroundingJointModelTest, NamingNoiseLeavesEveryCategoryPossible) {
  EXPECT_NEAR(NamingProbability(1.0, 10, 0.05), 0.95, 1e-12);
  EXPECT_NEAR(NamingProbability(0.0, 10, 0.05), 0.05 / 9, 1e-12);
  EXPECT_NEAR(NamingProbability(0.5, 10, 0.05), 0.475 + 0.025 / 9, 1e-12);
}

TEST(GroundingJointModelTest, ScoresAreLogLikelihoodsOfTheDescription) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const GroundingParams params = Joint();
  const Description d{Cat("table"), Relation::kLeftOf, Cat("chair")};
  const JointDescriptionTerms terms = JointTerms(g, k, d, params.joint);
  std::vector<InterpretationScore> scores;
  JointScores(g, k, params, Scheme::kStatistical, terms, d, InitialHypotheses(g).ranked.front(), scores);
  ASSERT_EQ(scores.size(), static_cast<std::size_t>(g.DirectedEdgeCount() * kInterpretationCount));
  double total = 0.0;
  for (const InterpretationScore& s : scores) {
    EXPECT_LE(s.score, 0.0);
    total += std::exp(s.score);
  }
  // Summed over the pieces it could mean and the readings, at most the probability of naming some located piece.
  EXPECT_LE(total, static_cast<double>(g.vertices.size()));
  // P(reference | located) sums to one over the located piece's edges.
  for (std::size_t v = 0; v < g.vertices.size(); ++v) {
    double sum = 0.0;
    for (int e = 0; e < g.DirectedEdgeCount(); ++e) {
      if (g.Located(e) == static_cast<int>(v)) sum += std::exp(terms.log_proximity[static_cast<std::size_t>(e)]);
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << g.vertices[v].id;
  }
}

TEST(GroundingJointModelTest, ThePieceNamedAgainIsCheaperTheSecondTime) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const GroundingParams params = Joint();
  const Description d{Cat("plant"), Relation::kBehind, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  const double first = set.ranked.front().matches.back().score;
  EXPECT_EQ(set.ranked.front().matches.back().directed_edge, g.FindDirected(g.VertexIndex("plant"), g.VertexIndex("chair")));
  // The categories are posteriors now: the plant and the chair are believed to be what they were called.
  EXPECT_GT(P(g, set.ranked.front().state, "plant", "plant"), 0.99);
  EXPECT_GT(P(g, set.ranked.front().state, "chair", "chair"), 0.9);
  set = Ground(g, k, set, d, params);
  EXPECT_GT(set.ranked.front().matches.back().score, first);
  EXPECT_NEAR(set.ranked.front().score, first + set.ranked.front().matches.back().score, 1e-9);  // a sum of logs
}

TEST(GroundingJointModelTest, ARepeatedDescriptionCountsOnce) {
  // The same words about the same pieces said three times: the reading that repeats the first adds 0 nats and
  // changes neither the categories nor the speaker's frame counts (without the rule the plant's and the chair's
  // p(f) would take the naming likelihood three times).
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const GroundingParams params = Joint();
  const Description d{Cat("plant"), Relation::kBehind, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  const Hypothesis once = set.ranked.front();
  for (int i = 0; i < 2; ++i) set = Ground(g, k, set, d, params);
  const Hypothesis& best = set.ranked.front();
  ASSERT_EQ(best.matches.size(), 3u);
  EXPECT_TRUE(SameReading(best.matches[0], best.matches[2]));
  EXPECT_TRUE(RepeatsEarlier(best.matches, 2));
  EXPECT_FALSE(RepeatsEarlier(best.matches, 0));
  EXPECT_EQ(best.matches[1].score, 0.0);
  EXPECT_EQ(best.matches[2].score, 0.0);
  EXPECT_DOUBLE_EQ(best.score, once.score);
  EXPECT_EQ(best.state.category, once.state.category);
  EXPECT_EQ(best.state.orientation, once.state.orientation);
  EXPECT_EQ(CountFrames(k, best.matches).total, CountFrames(k, once.matches).total);
  // Other words about the same pieces are new evidence.
  set = Ground(g, k, set, {Cat("chair"), Relation::kInFrontOf, Cat("plant")}, params);
  EXPECT_LT(set.ranked.front().matches.back().score, 0.0);
}

TEST(GroundingJointModelTest, ARepeatWeightAppliesOnceHoweverOftenTheDescriptionWasTold) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  GroundingParams params = Joint();
  params.joint.repeat_weight = 0.5;
  const Description d{Cat("plant"), Relation::kBehind, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  for (int i = 0; i < 2; ++i) set = Ground(g, k, set, d, params);
  const Hypothesis& best = set.ranked.front();
  ASSERT_EQ(best.matches.size(), 3u);
  ASSERT_TRUE(RepeatsEarlier(best.matches, 1) && RepeatsEarlier(best.matches, 2));
  // A repeat updates nothing, so the second and third tellings score the same reading from the same state: half of
  // it each (not a quarter for the third).
  EXPECT_LT(best.matches[1].score, 0.0);
  EXPECT_DOUBLE_EQ(best.matches[2].score, best.matches[1].score);
}

TEST(GroundingJointModelTest, AHeldDescriptionSaidTwiceAppliesItsUpdateOnceWhenResolved) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  GroundingParams params = Joint();
  params.ambiguity_margin = 2.0;  // nats
  const Description d{Cat("table"), Relation::kLeftOf, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  set = Ground(g, k, set, d, params);
  ASSERT_FALSE(set.held.empty());
  const int chair = g.VertexIndex("chair"), front = g.VertexIndex("table_front");
  while (!set.held.empty()) KeepPair(g, set, set.held.front().step, front, chair, params);
  // One Bayes update with naming noise 0.05 over 10 categories, not two.
  EXPECT_NEAR(P(g, set.ranked.front().state, "table_front", "table"), 0.7 * 0.95 / (0.7 * 0.95 + 0.3 * 0.05 / 9), 1e-9);
}

TEST(GroundingJointModelTest, AHeldPoorMatchIsNotConfirmedByItsOwnRepeat) {
  // "The armchair left of the chair" is ambiguous between two tables; the left one may be an armchair (0.3), the one
  // in front barely (0.02, below the category floor of 0.05): in the hypotheses that read it as the front table it
  // is a poor match. Told twice, it is still one reading: settling it must not take its own repeat for a second
  // description naming that piece, so the front table's p(armchair) stays where it was in those hypotheses.
  const FurnitureGraph g = BuildFurnitureGraph(
      {{0, 0}, 0},
      {{"chair", {3.0, 0.0}, {0.5, 0.5}, 0, Pf({{"chair", 0.7}, {"armchair", 0.2}, {"stool", 0.1}})},
       {"table_left", {3.0, 1.3}, {0.8, 0.8}, 0, Pf({{"table", 0.5}, {"armchair", 0.3}, {"stool", 0.2}})},
       {"table_front", {1.9, 0.0}, {0.6, 0.6}, 0, Pf({{"table", 0.68}, {"stool", 0.2}, {"chair", 0.1}, {"armchair", 0.02}})},
       {"plant", {4.1, 0.0}, {0.4, 0.4}, 0, Pf({{"plant", 0.9}, {"stool", 0.1}})}},
      DefaultKnowledge().categories.size(), {});
  const Knowledge& k = DefaultKnowledge();
  GroundingParams params = Joint();
  params.ambiguity_margin = 4.0;  // nats
  const Description d{Cat("armchair"), Relation::kLeftOf, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  set = Ground(g, k, set, d, params);
  ASSERT_FALSE(set.held.empty());
  const int front = g.VertexIndex("table_front");
  int front_readings = 0;
  for (const Hypothesis& h : set.ranked) {
    if (g.Located(h.matches[0].directed_edge) != front) continue;
    EXPECT_TRUE(IsPoorMatch(g, h.state, d, h.matches[0], params.category_floor));
    ++front_readings;
  }
  ASSERT_GT(front_readings, 0) << "no hypothesis reads the description as the front table";
  while (!set.held.empty()) SettleHeld(g, set, 0, params);
  for (const Hypothesis& h : set.ranked) {
    if (g.Located(h.matches[0].directed_edge) == front) {
      EXPECT_DOUBLE_EQ(P(g, h.state, "table_front", "armchair"), 0.02);
    }
  }
}

TEST(GroundingJointModelTest, AFrameTheSpeakerHasShownWinsTheDuplicate) {
  // Descriptions of the plant and of the tables in the relative frame first; then "the table is left of the chair":
  // the relative speaker means the table on the viewer's left, not the one an intrinsic reading would make fit.
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const GroundingParams params = Joint();
  HypothesisSet set = InitialHypotheses(g);
  for (int i = 0; i < 3; ++i) set = Ground(g, k, set, {Cat("plant"), Relation::kBehind, Cat("chair")}, params);
  set = Ground(g, k, set, {Cat("table"), Relation::kInFrontOf, Cat("chair")}, params);
  set = Ground(g, k, set, {Cat("table"), Relation::kLeftOf, Cat("chair")}, params);
  const Hypothesis& best = set.ranked.front();
  EXPECT_EQ(g.Located(best.matches.back().directed_edge), g.VertexIndex("table_left"));
  EXPECT_EQ(FrameOf(best.matches.back().interpretation), Frame::kRelative);
  EXPECT_EQ(CountFrames(k, best.matches).intrinsic, 0);
}

TEST(GroundingJointModelTest, TheNearestNeighbourIsTheLikelierReference) {
  // Two chairs to the right of a plant along the view, one near, one far: "the plant is left of the chair" means
  // the near one, although both fit the relation equally.
  const FurnitureGraph g = BuildFurnitureGraph(
      {{0, 0}, 0},
      {{"plant", {3.0, 0.0}, {0.4, 0.4}, 0, Pf({{"plant", 0.8}, {"stool", 0.2}})},
       {"near", {3.0, -0.9}, {0.5, 0.5}, 0, Pf({{"chair", 0.7}, {"stool", 0.3}})},
       {"far", {3.0, 1.5}, {0.5, 0.5}, 0, Pf({{"chair", 0.7}, {"stool", 0.3}})}},
      DefaultKnowledge().categories.size(), {});
  const HypothesisSet set = Ground(g, DefaultKnowledge(), InitialHypotheses(g), {Cat("chair"), Relation::kRightOf, Cat("plant")}, Joint());
  EXPECT_EQ(g.Located(set.ranked.front().matches.back().directed_edge), g.VertexIndex("near"));
}

TEST(GroundingJointModelTest, TheRelativeFrameAlongTheLineOfSightFits) {
  // A reference far to the viewer's left (63 degrees): along the viewing direction the located piece is mostly
  // behind it, along the line of sight to it it is to its right - and the line-of-sight fit counts.
  const FurnitureGraph g = BuildFurnitureGraph(
      {{0, 0}, 0},
      {{"plant", {2.0, 4.0}, {0.4, 0.4}, 0, Pf({{"plant", 0.8}, {"stool", 0.2}})},
       {"stool", {2.715, 3.642}, {0.4, 0.4}, 0, Pf({{"stool", 0.8}, {"plant", 0.2}})}},
      DefaultKnowledge().categories.size(), {});
  const int e = g.FindDirected(1, 0);
  const Distribution4& sight = g.edges[0].line_of_sight[static_cast<std::size_t>(e % 2)];
  EXPECT_GT(sight[static_cast<std::size_t>(Relation::kRightOf)], 0.9);
  EXPECT_GT(g.Visual(e)[static_cast<std::size_t>(Relation::kBehind)], 0.5);
  const Description d{Cat("stool"), Relation::kRightOf, Cat("plant")};
  const double s_with = Ground(g, DefaultKnowledge(), InitialHypotheses(g), d, Joint()).ranked.front().score;
  const double s_without = Ground(g, DefaultKnowledge(), InitialHypotheses(g), d, Joint(0.0)).ranked.front().score;
  EXPECT_GT(s_with, s_without + 0.3);
}

TEST(GroundingJointModelTest, ADescriptionThatFitsNoPieceMovesNoCategory) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const Description d{Cat("cupboard"), Relation::kBehind, Cat("chair")};  // nothing is believed to be a cupboard
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, Joint());
  EXPECT_TRUE(IsPoorMatch(g, set.ranked.front().state, d, set.ranked.front().matches.back(), 0.05));
  for (const Hypothesis& h : set.ranked) EXPECT_EQ(h.state.category, g.initial.category);
}

TEST(GroundingJointModelTest, AnAmbiguousStepIsHeldAndItsResolutionAppliesTheBayesUpdate) {
  const FurnitureGraph g = TwoTables();
  const Knowledge& k = DefaultKnowledge();
  const GroundingParams params = [] {
    GroundingParams p = Joint();
    p.ambiguity_margin = 2.0;  // nats
    return p;
  }();
  const Description d{Cat("table"), Relation::kLeftOf, Cat("chair")};
  HypothesisSet set = Ground(g, k, InitialHypotheses(g), d, params);
  ASSERT_EQ(set.held.size(), 1u);
  for (const Hypothesis& h : set.ranked) EXPECT_EQ(h.state.category, g.initial.category);
  const int chair = g.VertexIndex("chair"), front = g.VertexIndex("table_front");
  KeepPair(g, set, 0, front, chair, params);
  EXPECT_TRUE(set.held.empty());
  const GraphState& s = set.ranked.front().state;
  // Bayes with naming noise 0.05 over 10 categories: 0.7 x 0.95 / (0.7 x 0.95 + 0.3 x 0.05 / 9) = 0.9975.
  EXPECT_NEAR(P(g, s, "table_front", "table"), 0.7 * 0.95 / (0.7 * 0.95 + 0.3 * 0.05 / 9), 1e-9);
  EXPECT_EQ(P(g, s, "table_left", "table"), 0.7);
}

}  // namespace
}  // namespace anchordb::engine::grounding
