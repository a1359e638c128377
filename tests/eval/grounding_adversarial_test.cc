// The adversarial participant family of issue 17 (tests/eval/grounding_adversarial.h), 30 rooms per speaker type:
// issue 17's model (ambiguity held, the category floor, the room's orientation prior) beats the thesis' on
// descriptions in the same run. The issue's own bars (descriptions right >= 92 %, quality-A graphs 100 %, quality-B
// graphs >= 85 %) do not hold yet (0.80, 0.96, 0.43; anchordb_eval_grounding_adversarial prints the table): they are
// left open in the issue rather than asserted at a weaker level.
#include <gtest/gtest.h>

#include "tests/eval/grounding_adversarial.h"

namespace anchordb::eval::adversarial {
namespace {

const Table& Seeded() {
  static const Table kTable = Evaluate(30, 1);
  return kTable;
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
