// Eqs. 5.1-5.5 of the thesis computed by hand on a three-piece scene and compared with the engine; the geometry
// of the relative and intrinsic frames; the soft initial relations.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/grounding/grounding.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace grounding_model_test {

constexpr double kTol = 1e-12;

// Three categories: chair (vehicle), plant (no front), shelf (opposite). Statistical prior: P(intrinsic) = 0.3 for
// vehicles, 0.4 for opposite objects, 0.1 without a front, in every cell where the frames differ.
Knowledge ThreeCategoryKnowledge() {
  Knowledge k;
  k.categories = CategoryTable({{"chair", "chair", Nature::kVehicle, {"chair"}},
                                {"plant", "plant", Nature::kNone, {"plant"}},
                                {"shelf", "shelf", Nature::kOpposite, {"shelf"}}});
  const double p_int[3] = {0.3, 0.4, 0.1};
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

// v0 chair, v1 plant, v2 shelf (seen as a chair, as in figure 5.6). Directed edges: 0 = v0 rel v1, 1 = v1 rel v0,
// 2 = v0 rel v2, 3 = v2 rel v0, 4 = v1 rel v2, 5 = v2 rel v1. Relation order: left_of, right_of, in_front_of, behind.
FurnitureGraph ThreePieceGraph() {
  FurnitureGraph g;
  g.category_count = 3;
  g.vertices = {{"v0", {}, {}, 0.0}, {"v1", {}, {}, 0.0}, {"v2", {}, {}, 0.0}};
  Edge e01{0, 1, 0.5, {Distribution4{0.1, 0.7, 0.1, 0.1}, Distribution4{0.7, 0.1, 0.1, 0.1}}};
  Edge e02{0, 2, 0.5, {Distribution4{0.1, 0.1, 0.7, 0.1}, Distribution4{0.1, 0.1, 0.1, 0.7}}};
  Edge e12{1, 2, 1.2, {Distribution4{0.2, 0.1, 0.6, 0.1}, Distribution4{0.1, 0.2, 0.1, 0.6}}};
  g.edges = {e01, e02, e12};
  g.initial.category = {0.6, 0.1, 0.3,   // v0
                        0.2, 0.7, 0.1,   // v1
                        0.5, 0.1, 0.4};  // v2
  g.initial.orientation.assign(12, 0.25);
  for (const Edge& e : g.edges) {
    for (const Distribution4& p : e.visual) g.initial.relation.insert(g.initial.relation.end(), p.begin(), p.end());
  }
  return g;
}

constexpr int kChair = 0, kPlant = 1, kShelf = 2;
constexpr int kRel = 0, kIntLeft = 1, kIntRight = 2, kIntFront = 3, kIntBack = 4;

TEST(GroundingFramesTest, IntrinsicWordsFollowVehicleAndOppositeNature) {
  // Figure 5.2: a chair whose front points to the viewer's left; the plant to its right (relative) is behind it.
  EXPECT_EQ(IntrinsicToRelative(Relation::kBehind, Nature::kVehicle, Orientation::kLeft), Relation::kRightOf);
  // A chair facing the viewer: its left is the viewer's right. A shelf facing the viewer: its left is the viewer's.
  EXPECT_EQ(IntrinsicToRelative(Relation::kLeftOf, Nature::kVehicle, Orientation::kFront), Relation::kRightOf);
  EXPECT_EQ(IntrinsicToRelative(Relation::kLeftOf, Nature::kOpposite, Orientation::kFront), Relation::kLeftOf);
  // Seen from behind, a chair's left is the viewer's left and its front is towards the viewer's "behind".
  EXPECT_EQ(IntrinsicToRelative(Relation::kLeftOf, Nature::kVehicle, Orientation::kBack), Relation::kLeftOf);
  EXPECT_EQ(IntrinsicToRelative(Relation::kInFrontOf, Nature::kVehicle, Orientation::kBack), Relation::kBehind);
  // Front pointing right: a vehicle's left is away from the viewer, an opposite object's left is towards the viewer.
  EXPECT_EQ(IntrinsicToRelative(Relation::kLeftOf, Nature::kVehicle, Orientation::kRight), Relation::kBehind);
  EXPECT_EQ(IntrinsicToRelative(Relation::kLeftOf, Nature::kOpposite, Orientation::kRight), Relation::kInFrontOf);
  for (int n = 0; n < kNatureCount; ++n) {
    for (int o = 0; o < kOrientationCount; ++o) {
      for (int r = 0; r < kRelationCount; ++r) {
        const auto rel = static_cast<Relation>(r);
        EXPECT_EQ(IntrinsicToRelative(RelativeToIntrinsic(rel, static_cast<Nature>(n), static_cast<Orientation>(o)),
                                      static_cast<Nature>(n), static_cast<Orientation>(o)), rel);
      }
    }
  }
  // The words of both frames coincide for an opposite object facing the viewer, in every direction.
  for (int r = 0; r < kRelationCount; ++r) {
    EXPECT_TRUE(FramePrior::FramesCoincide(Nature::kOpposite, Orientation::kFront, static_cast<Relation>(r)));
  }
  EXPECT_FALSE(FramePrior::FramesCoincide(Nature::kVehicle, Orientation::kLeft, Relation::kLeftOf));
}

TEST(GroundingModelTest, InitialRelationsAreSoftByAngle) {
  // Viewer at the origin looking along map +x: map +y is the viewer's left.
  Viewpoint view{{0.0, 0.0}, 0.0};
  const double kappa = 3.0;
  const double z = std::exp(kappa) + 2.0 + std::exp(-kappa);
  const Distribution4 left = RelationFromOffset(view.ToViewer({0.0, 1.5}), kappa);
  EXPECT_NEAR(left[0], std::exp(kappa) / z, kTol);
  EXPECT_NEAR(left[1], std::exp(-kappa) / z, kTol);
  EXPECT_NEAR(left[2], 1.0 / z, kTol);
  EXPECT_NEAR(left[3], 1.0 / z, kTol);
  // Nearer to the viewer = in front of; a diagonal splits evenly between its two relations.
  const Distribution4 front = RelationFromOffset(view.ToViewer({-1.0, 0.0}), kappa);
  EXPECT_NEAR(front[2], std::exp(kappa) / z, kTol);
  const Distribution4 diagonal = RelationFromOffset(view.ToViewer({1.0, -1.0}), kappa);  // behind and to the right
  EXPECT_NEAR(diagonal[1], diagonal[3], kTol);
  EXPECT_GT(diagonal[1], 0.45);
  // A viewer looking along map +y (heading 90 deg): map -x is the viewer's left.
  Viewpoint turned{{0.0, 0.0}, M_PI / 2};
  EXPECT_NEAR(RelationFromOffset(turned.ToViewer({-1.0, 0.0}), kappa)[0], std::exp(kappa) / z, 1e-9);
}

TEST(GroundingModelTest, GraphFromFurnitureHasEdgesOnlyBetweenNearPieces) {
  Viewpoint view{{0.0, 0.0}, 0.0};
  const std::vector<double> pf = {0.6, 0.1, 0.3};
  std::vector<FurnitureInput> f = {{"sofa", {3.0, 0.0}, {0.9, 2.0}, 0.0, pf},
                                   {"plant", {3.0, 1.8}, {0.4, 0.4}, 0.0, pf},
                                   {"table", {1.8, 0.0}, {0.6, 1.0}, 0.0, pf},
                                   {"far", {9.0, 9.0}, {0.5, 0.5}, 0.0, pf}};
  const FurnitureGraph g = BuildFurnitureGraph(view, f, 3, GraphParams{});
  ASSERT_EQ(g.edges.size(), 3u);  // sofa-plant (gap 0.6), sofa-table (0.45), plant-table (1.30); "far" has none
  EXPECT_NEAR(g.edges[0].gap_m, 0.6, 1e-12);
  EXPECT_NEAR(g.edges[1].gap_m, 0.45, 1e-12);
  EXPECT_NEAR(g.edges[2].gap_m, std::hypot(0.7, 1.1), 1e-12);
  // The plant is to the left of the sofa; the sofa to the right of the plant; the table in front of the sofa.
  const int plant_of_sofa = g.FindDirected(1, 0), table_of_sofa = g.FindDirected(2, 0);
  EXPECT_GT(g.Visual(plant_of_sofa)[static_cast<int>(Relation::kLeftOf)], 0.9);
  EXPECT_GT(g.Visual(g.FindDirected(0, 1))[static_cast<int>(Relation::kRightOf)], 0.9);
  EXPECT_GT(g.Visual(table_of_sofa)[static_cast<int>(Relation::kInFrontOf)], 0.9);
  EXPECT_EQ(g.FindDirected(3, 0), -1);
  for (double p : g.initial.orientation) EXPECT_EQ(p, 0.25);
  // Errors: fewer than two pieces; no edge at all.
  EXPECT_THROW(BuildFurnitureGraph(view, {f[0]}, 3, GraphParams{}), Error);
  EXPECT_THROW(BuildFurnitureGraph(view, {f[0], f[3]}, 3, GraphParams{}), Error);
}

TEST(GroundingModelTest, ScoresMatchEquations52And53ByHand) {
  const Knowledge k = ThreeCategoryKnowledge();
  const FurnitureGraph g = ThreePieceGraph();
  // "the plant is behind the chair" on directed edge 1 (v1 located, v0 reference).
  const Description plant_behind_chair{kPlant, Relation::kBehind, kChair};
  const auto s = ScoreInterpretations(g, g.initial, k, Scheme::kStatistical, plant_behind_chair, 1);
  const double categories = 0.7 + 0.6;  // P(plant | v1) + P(chair | v0)
  // Relative: P(behind | e) = 0.1 times max over o of P(o) P(relative | vehicle, o, behind) = 0.25 x 0.7.
  EXPECT_EQ(s[kRel].relative, Relation::kBehind);
  EXPECT_NEAR(s[kRel].rho, 0.1 * 0.25 * 0.7, kTol);
  EXPECT_NEAR(s[kRel].score, (categories + 0.1 * 0.25 * 0.7) / 3.0, kTol);
  // Intrinsic, chair front to the viewer's right: "behind" = -front = the viewer's left, P(left_of | e) = 0.7.
  EXPECT_EQ(s[kIntRight].relative, Relation::kLeftOf);
  EXPECT_NEAR(s[kIntRight].rho, 0.7 * 0.3 * 0.25, kTol);
  EXPECT_NEAR(s[kIntRight].score, (categories + 0.7 * 0.3 * 0.25) / 3.0, kTol);
  // Front to the left: "behind" = right_of (0.1); facing the viewer: behind (0.1; both frames give the same word
  // there, the frame probability is still the table's); facing away: in_front_of (0.1).
  EXPECT_EQ(s[kIntLeft].relative, Relation::kRightOf);
  EXPECT_NEAR(s[kIntLeft].rho, 0.1 * 0.3 * 0.25, kTol);
  EXPECT_EQ(s[kIntFront].relative, Relation::kBehind);
  EXPECT_NEAR(s[kIntFront].rho, 0.1 * 0.3 * 0.25, kTol);
  EXPECT_EQ(s[kIntBack].relative, Relation::kInFrontOf);
  EXPECT_NEAR(s[kIntBack].rho, 0.1 * 0.3 * 0.25, kTol);

  // The third piece: "the chair is in front of the shelf" on directed edge 2 (v0 located, v2 reference). The
  // shelf is an opposite object: P(relative) = 0.6.
  const auto t = ScoreInterpretations(g, g.initial, k, Scheme::kStatistical, {kChair, Relation::kInFrontOf, kShelf}, 2);
  EXPECT_NEAR(t[kRel].score, (0.6 + 0.4 + 0.7 * 0.25 * 0.6) / 3.0, kTol);
  // Opposite object with its front to the viewer's left: its front side is the viewer's left (P = 0.1 here).
  EXPECT_EQ(t[kIntLeft].relative, Relation::kLeftOf);
  EXPECT_NEAR(t[kIntLeft].score, (0.6 + 0.4 + 0.1 * 0.4 * 0.25) / 3.0, kTol);
  // ... and on the wrong edge 4 (v1 located, v2 reference) the categories fit less: P(chair | v1) = 0.2.
  const auto w = ScoreInterpretations(g, g.initial, k, Scheme::kStatistical, {kChair, Relation::kInFrontOf, kShelf}, 4);
  EXPECT_NEAR(w[kRel].score, (0.2 + 0.4 + 0.6 * 0.25 * 0.6) / 3.0, kTol);
}

TEST(GroundingModelTest, UpdatesMatchEquations54And55ByHand) {
  const Knowledge k = ThreeCategoryKnowledge();
  const FurnitureGraph g = ThreePieceGraph();
  const Description plant_behind_chair{kPlant, Relation::kBehind, kChair};
  const double sigma = 2.0;
  // Relative reading on directed edge 1: p(f) of v1 towards plant, of v0 towards chair, p(r) towards behind.
  Match relative{1, kRel, Relation::kBehind, Scheme::kStatistical, 0.0};
  const GraphState a = ApplyMatch(g, g.initial, k, plant_behind_chair, relative, sigma);
  const std::vector<double> v0 = {0.6 + 0.4 / 2, 0.1 - 0.1 / 2, 0.3 - 0.3 / 2};
  const std::vector<double> v1 = {0.2 - 0.2 / 2, 0.7 + 0.3 / 2, 0.1 - 0.1 / 2};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.category[static_cast<std::size_t>(i)], v0[static_cast<std::size_t>(i)], kTol);
    EXPECT_NEAR(a.category[static_cast<std::size_t>(3 + i)], v1[static_cast<std::size_t>(i)], kTol);
    EXPECT_EQ(a.category[static_cast<std::size_t>(6 + i)], g.initial.category[static_cast<std::size_t>(6 + i)]);  // v2 untouched
  }
  const std::vector<double> r1 = {0.35, 0.05, 0.05, 0.55};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(a.relation[static_cast<std::size_t>(4 + i)], r1[static_cast<std::size_t>(i)], kTol);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(a.relation[static_cast<std::size_t>(i)], g.initial.relation[static_cast<std::size_t>(i)]);  // other direction untouched
  EXPECT_EQ(a.orientation, g.initial.orientation);  // a relative reading says nothing about orientation

  // Eq. 5.5 for "behind" on directed edge 1 (visual p(r) = left 0.7, right 0.1, front 0.1, behind 0.1): the
  // orientation x makes "behind" mean I(behind | x): left -> right_of 0.1, right -> left_of 0.7,
  // front -> behind 0.1, back -> in_front_of 0.1 (already normalised).
  const Distribution4 target = OrientationTarget(g, 1, Relation::kBehind, Nature::kVehicle);
  const Distribution4 expected_target = {0.1, 0.7, 0.1, 0.1};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(target[static_cast<std::size_t>(i)], expected_target[static_cast<std::size_t>(i)], kTol);
  Match intrinsic{1, kIntRight, Relation::kLeftOf, Scheme::kStatistical, 0.0};
  const GraphState b = ApplyMatch(g, g.initial, k, plant_behind_chair, intrinsic, sigma);
  const std::vector<double> o0 = {0.175, 0.475, 0.175, 0.175};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(b.orientation[static_cast<std::size_t>(i)], o0[static_cast<std::size_t>(i)], kTol);
  for (int i = 4; i < 12; ++i) EXPECT_EQ(b.orientation[static_cast<std::size_t>(i)], 0.25);
  // The edge learns the relation r' of the interpretation (left_of), not the spoken word.
  const std::vector<double> r1b = {0.85, 0.05, 0.05, 0.05};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(b.relation[static_cast<std::size_t>(4 + i)], r1b[static_cast<std::size_t>(i)], kTol);

  // Damping: sigma = 1 replaces, a large sigma barely moves.
  double p[3] = {0.2, 0.3, 0.5};
  const double one_hot[3] = {0.0, 1.0, 0.0};
  DampedUpdate(p, one_hot, 3, 1.0);
  EXPECT_NEAR(p[1], 1.0, kTol);
  double q[3] = {0.2, 0.3, 0.5};
  DampedUpdate(q, one_hot, 3, 100.0);
  EXPECT_NEAR(q[1], 0.3 + 0.7 / 100.0, kTol);
}

TEST(GroundingModelTest, FirstStepRanksEveryInterpretationOfEveryEdge) {
  const Knowledge k = ThreeCategoryKnowledge();
  const FurnitureGraph g = ThreePieceGraph();
  GroundingParams params;
  params.n_best = 5;
  params.sigma = 2.0;
  params.schemes = {Scheme::kStatistical};
  const HypothesisSet next = Ground(g, k, InitialHypotheses(g), {kPlant, Relation::kBehind, kChair}, params);
  ASSERT_EQ(next.ranked.size(), 5u);
  EXPECT_EQ(next.step, 1);
  // By hand (see ScoresMatchEquations52And53ByHand): on edge 1 intrinsic right 0.45083 > relative 0.43917 >
  // intrinsic left = front = back 0.43583 (ties kept in interpretation order); the best other edge (4: v1
  // located, v2 reference, intrinsic with the front away) reaches only (0.7 + 0.5 + 0.6 x 0.3 x 0.25) / 3 = 0.415.
  const int expected_interpretation[5] = {kIntRight, kRel, kIntLeft, kIntFront, kIntBack};
  for (std::size_t i = 0; i < 5; ++i) {
    const Hypothesis& h = next.ranked[i];
    EXPECT_EQ(h.id, static_cast<std::int64_t>(i + 1));
    EXPECT_EQ(h.parent_id, 0);
    ASSERT_EQ(h.matches.size(), 1u);
    EXPECT_EQ(h.matches[0].directed_edge, 1);
    EXPECT_EQ(h.matches[0].interpretation, expected_interpretation[i]) << i;
    EXPECT_EQ(h.lineage_ranks, std::vector<int>{static_cast<int>(i)});
  }
  EXPECT_NEAR(next.ranked[0].score, (1.3 + 0.0525) / 3.0, kTol);
  EXPECT_NEAR(next.ranked[1].score, (1.3 + 0.0175) / 3.0, kTol);
  EXPECT_NEAR(next.ranked[2].score, (1.3 + 0.0075) / 3.0, kTol);
  EXPECT_NEAR(next.ranked[4].score, (1.3 + 0.0075) / 3.0, kTol);
  // The updated graphs: the best is eq. 5.4 applied to G0 with the relative reading.
  EXPECT_EQ(next.ranked[0].state,
            ApplyMatch(g, g.initial, k, {kPlant, Relation::kBehind, kChair}, next.ranked[0].matches[0], 2.0));
}

}  // namespace
}  // namespace anchordb::engine::grounding
