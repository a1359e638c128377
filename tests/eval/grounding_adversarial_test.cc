// The adversarial participant family of issue 17 (tests/eval/grounding_adversarial.h): issue 17's sequential model
// (ambiguity held, the category floor, the room's orientation prior) beats the thesis' on descriptions in the same
// run (seeds 1-30), and the joint model (engine/grounding/joint_model.h, the service's default) meets the issue's
// bars - descriptions right >= 92 %, quality-A graphs all right 100 %, quality-B graphs all right >= 85 % - on
// seeds 121-240, 120 rooms per speaker type that no constant or rule of the model was chosen on (seeds 1-30 chose
// the constants, 31-120 were looked at for the repeat rule; engine/grounding/README.md). anchordb_eval_grounding_
// adversarial (no options) prints the table per 30-seed block of 1-240 and pooled, the
// held-out blocks apart.
#include <gtest/gtest.h>

#include "tests/eval/grounding_adversarial.h"

namespace anchordb::eval::adversarial {
namespace {

constexpr int kHeldOutFirstSeed = 121;
constexpr int kHeldOutRooms = 120;

const Table& Seeded() {
  static const Table kTable = Evaluate(30, 1, {Model::kThesis, Model::kIssue17});
  return kTable;
}

const Table& HeldOut() {
  static const Table kTable = Evaluate(kHeldOutRooms, kHeldOutFirstSeed, {Model::kJoint});
  return kTable;
}

TEST(GroundingAdversarialTest, IssueSeventeenModelBeatsTheThesisModelOnDescriptions) {
  for (int q = 0; q < 2; ++q) {
    const Cell before = Seeded().Over(Model::kThesis, q), after = Seeded().Over(Model::kIssue17, q);
    EXPECT_EQ(before.descriptions, after.descriptions);
    EXPECT_GT(after.DescriptionRate(), before.DescriptionRate() + 0.03) << "quality " << q;
  }
}

TEST(GroundingAdversarialTest, JointModelMeetsTheIssueBarsOnSeedsNotUsedForTuning) {
  const Cell a = HeldOut().Over(Model::kJoint, 0), b = HeldOut().Over(Model::kJoint, 1);
  for (int q = 0; q < 2; ++q) {
    for (int s = 0; s < 3; ++s) {
      const Cell& c = HeldOut().cells[static_cast<int>(Model::kJoint)][q][s];
      EXPECT_EQ(c.rooms, kHeldOutRooms);
      const std::string cell = std::string(SpeakerName(static_cast<Speaker>(s))) + "_" + "AB"[q];
      RecordProperty("graphs_right_" + cell, std::to_string(c.GraphRate()));
      RecordProperty("descriptions_right_" + cell, std::to_string(c.DescriptionRate()));
    }
  }
  RecordProperty("descriptions_right", std::to_string(HeldOut().DescriptionRate(Model::kJoint)));
  EXPECT_GT(a.descriptions, 20L * kHeldOutRooms);  // rooms with 10-20 descriptions were grounded
  EXPECT_EQ(a.graphs_right, a.rooms);
  EXPECT_GE(b.GraphRate(), 0.85);
  EXPECT_GE(HeldOut().DescriptionRate(Model::kJoint), 0.92);
}

}  // namespace
}  // namespace anchordb::eval::adversarial
