// The bars of issue 5 on the seeded synthetic-participant evaluation (thesis 5.4.2): with adaptation at quality A
// at least 92 % of descriptions and 67 % of whole sequences grounded correctly; adaptation beats no adaptation for
// relative-frame participants; the piece quality B misclassifies is corrected in at least 85 % of sequences.
#include <gtest/gtest.h>

#include "tests/eval/grounding_eval.h"

namespace anchordb::eval {
namespace {

const Evaluation& Seeded() {
  static const Evaluation kEvaluation = Evaluate(30, 1, EvalOptions{});
  return kEvaluation;
}

// The service's defaults since issue 17: ambiguous descriptions held, poor matches move no category.
EvalOptions ServiceDefaults() {
  EvalOptions o;
  o.ambiguity_margin = 0.02;
  o.category_floor = 0.05;
  return o;
}

const Evaluation& SeededWithAmbiguity() {
  static const Evaluation kEvaluation = Evaluate(30, 1, ServiceDefaults());
  return kEvaluation;
}

TEST(GroundingEvalTest, IssueFiveBarsHoldWithAmbiguityHeldAndTheCategoryFloor) {
  const Tally a = SeededWithAmbiguity().Over(Quality::kA, Condition::kAdaptation);
  const Tally b = SeededWithAmbiguity().Over(Quality::kB, Condition::kAdaptation);
  RecordProperty("descriptions_correct_A", std::to_string(a.DescriptionRate()));
  RecordProperty("corrected_B", std::to_string(b.CorrectedRate()));
  EXPECT_GE(a.DescriptionRate(), 0.92);
  EXPECT_GE(a.SequenceRate(), 0.67);
  EXPECT_LT(1.0 - a.VertexRate(), 0.03);
  EXPECT_GE(b.CorrectedRate(), 0.85);
  EXPECT_LT(1.0 - b.VertexRate(), 0.03);
  // Asking back is worth it: most held descriptions were matched wrongly at that moment.
  EXPECT_GT(a.held, 0);
  EXPECT_GE(2 * a.held_wrong, a.held);
}

// The joint model (engine/grounding/joint_model.h) with the service's joint defaults: margin in nats.
const Evaluation& SeededJoint() {
  static const Evaluation kEvaluation = [] {
    EvalOptions o;
    o.model = engine::grounding::Model::kJoint;
    o.ambiguity_margin = 0.3;
    o.category_floor = 0.05;
    return Evaluate(30, 1, o);
  }();
  return kEvaluation;
}

TEST(GroundingEvalTest, IssueFiveBarsHoldWithTheJointModel) {
  const Tally a = SeededJoint().Over(Quality::kA, Condition::kAdaptation);
  const Tally b = SeededJoint().Over(Quality::kB, Condition::kAdaptation);
  RecordProperty("descriptions_correct_A", std::to_string(a.DescriptionRate()));
  RecordProperty("sequences_correct_A", std::to_string(a.SequenceRate()));
  RecordProperty("corrected_B", std::to_string(b.CorrectedRate()));
  EXPECT_GE(a.DescriptionRate(), 0.92);
  EXPECT_GE(a.SequenceRate(), 0.67);
  EXPECT_LT(1.0 - a.VertexRate(), 0.03);
  EXPECT_GE(b.CorrectedRate(), 0.85);
  EXPECT_LT(1.0 - b.VertexRate(), 0.03);
  EXPECT_GT(a.held, 0);  // ambiguity is still asked back
}

TEST(GroundingEvalTest, AdaptationAtQualityAReachesTheThesis) {
  const Tally t = Seeded().Over(Quality::kA, Condition::kAdaptation);
  RecordProperty("descriptions_correct", std::to_string(t.DescriptionRate()));
  RecordProperty("sequences_correct", std::to_string(t.SequenceRate()));
  EXPECT_EQ(t.sequences, 90);
  EXPECT_GE(t.DescriptionRate(), 0.92);
  EXPECT_GE(t.SequenceRate(), 0.67);
  EXPECT_LT(1.0 - t.VertexRate(), 0.03);  // thesis: under 3 % mislabelled at A and B with adaptation
}

TEST(GroundingEvalTest, AdaptationBeatsNoAdaptationForRelativeFrameParticipants) {
  long with = 0, without = 0, total = 0;
  for (int q = 0; q < 3; ++q) {
    const Tally& a = Seeded().tallies[q][static_cast<int>(Condition::kAdaptation)][static_cast<int>(Speaker::kRelative)];
    const Tally& n = Seeded().tallies[q][static_cast<int>(Condition::kNoAdaptation)][static_cast<int>(Speaker::kRelative)];
    with += a.descriptions_correct;
    without += n.descriptions_correct;
    total += a.descriptions;
    EXPECT_GE(a.descriptions_correct, n.descriptions_correct) << QualityName(static_cast<Quality>(q));
  }
  RecordProperty("relative_with_adaptation", std::to_string(double(with) / total));
  RecordProperty("relative_without_adaptation", std::to_string(double(without) / total));
  EXPECT_GT(with, without);
}

TEST(GroundingEvalTest, MisclassifiedPieceOfQualityBIsCorrected) {
  const Tally t = Seeded().Over(Quality::kB, Condition::kAdaptation);
  RecordProperty("corrected", std::to_string(t.CorrectedRate()));
  EXPECT_EQ(t.misclassified, 90);  // every B sequence starts with one piece wrong
  EXPECT_GE(t.CorrectedRate(), 0.85);
  EXPECT_LT(1.0 - t.VertexRate(), 0.03);
}

TEST(GroundingEvalTest, SequencesRevertToLowerRankedHypotheses) {
  // The thesis saw final sequences run through hypotheses first ranked 60th-70th; with n = 100 the evaluation
  // does too, which is why n must be in the hundreds.
  EXPECT_GE(Seeded().Over(Quality::kA, Condition::kAdaptation).worst_rank_reverted, 50);
}

TEST(GroundingEvalTest, ParticipantsAreReproducible) {
  const engine::grounding::Knowledge& k = engine::grounding::DefaultKnowledge();
  const Participant a = MakeParticipant(7, Speaker::kPrior, k), b = MakeParticipant(7, Speaker::kPrior, k);
  ASSERT_EQ(a.descriptions.size(), b.descriptions.size());
  EXPECT_GE(a.descriptions.size(), 12u);
  EXPECT_LE(a.descriptions.size(), 20u);
  EXPECT_GE(a.pieces.size(), 6u);
  EXPECT_LE(a.pieces.size(), 8u);
  for (std::size_t i = 0; i < a.descriptions.size(); ++i) EXPECT_EQ(a.descriptions[i].word, b.descriptions[i].word);
  const TrialResult r1 = RunTrial(a, Quality::kB, Condition::kAdaptation, k, EvalOptions{});
  const TrialResult r2 = RunTrial(b, Quality::kB, Condition::kAdaptation, k, EvalOptions{});
  EXPECT_EQ(r1.descriptions_correct, r2.descriptions_correct);
  EXPECT_EQ(r1.worst_rank_reverted, r2.worst_rank_reverted);
}

}  // namespace
}  // namespace anchordb::eval
