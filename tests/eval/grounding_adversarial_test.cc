// The acceptance bars of issue 17 on the adversarial participant family (tests/eval/grounding_adversarial.h), 30
// rooms per speaker type: descriptions right >= 92 % overall, quality-A graphs all right 100 %, quality-B graphs all
// right >= 85 %; and issue 17's model beats the thesis' on descriptions in the same run. The bars did not hold when
// they were written (figures in the branch's report): these tests say so rather than a weaker bar.
#include <gtest/gtest.h>

#include "tests/eval/grounding_adversarial.h"

namespace anchordb::eval::adversarial {
namespace {

const Table& Seeded() {
  static const Table kTable = Evaluate(30, 1);
  return kTable;
}

TEST(GroundingAdversarialTest, IssueSeventeenBars) {
  const Cell a = Seeded().Over(Model::kIssue17, 0), b = Seeded().Over(Model::kIssue17, 1);
  const double overall = double(a.right + b.right) / double(a.descriptions + b.descriptions);
  RecordProperty("descriptions_right", std::to_string(overall));
  RecordProperty("graphs_right_A", std::to_string(a.GraphRate()));
  RecordProperty("graphs_right_B", std::to_string(b.GraphRate()));
  EXPECT_EQ(a.rooms, 90);
  EXPECT_GE(overall, 0.92);
  EXPECT_EQ(a.graphs_right, a.rooms);
  EXPECT_GE(b.GraphRate(), 0.85);
}

TEST(GroundingAdversarialTest, IssueSeventeenModelBeatsTheThesisModelOnDescriptions) {
  for (int q = 0; q < 2; ++q) {
    const Cell before = Seeded().Over(Model::kThesis, q), after = Seeded().Over(Model::kIssue17, q);
    EXPECT_EQ(before.descriptions, after.descriptions);
    EXPECT_GT(after.DescriptionRate(), before.DescriptionRate() + 0.03) << "quality " << q;
  }
}

}  // namespace
}  // namespace anchordb::eval::adversarial
