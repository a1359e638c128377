// Labels from dialog and operators (engine/events/labels.h): normalisation, the distribution, the top label.
#include <gtest/gtest.h>

#include "engine/events/labels.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace events_labels_test {

TEST(EventsLabelsTest, NormalisedLowercaseTrimmedAndCollapsed) {
  EXPECT_EQ(NormaliseLabel("  Car   Keys ", 64, "label"), "car keys");
  EXPECT_EQ(NormaliseLabel("mug", 3, "label"), "mug");
  const auto code = [](std::string_view raw, std::size_t max) {
    try {
      NormaliseLabel(raw, max, "label");
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "label");
      return e.code();
    }
    return ErrorCode::kInternal;
  };
  EXPECT_EQ(code("   ", 64), ErrorCode::kUnprocessable);
  EXPECT_EQ(code("", 64), ErrorCode::kUnprocessable);
  EXPECT_EQ(code("mugs", 3), ErrorCode::kUnprocessable);
  EXPECT_EQ(code(std::string("a\x01" "b"), 64), ErrorCode::kInvalidArgument);
}

TEST(EventsLabelsTest, DialogAddsEvidenceAnOperatorReplacesIt) {
  LabelWeights w = AddLabel({}, "keys", false);
  w = AddLabel(w, "keys", false);
  w = AddLabel(w, "wallet", false);
  EXPECT_EQ(w, (LabelWeights{{"keys", 2.0}, {"wallet", 1.0}}));
  EXPECT_EQ(TopLabel(w), "keys");
  EXPECT_NEAR(LabelProbability(w, "keys"), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(LabelProbability(w, "mug"), 0.0);
  EXPECT_EQ(LabelDistribution(w), (LabelWeights{{"keys", 2.0 / 3.0}, {"wallet", 1.0 / 3.0}}));
  EXPECT_EQ(AddLabel(w, "car keys", true), (LabelWeights{{"car keys", 1.0}}));
  EXPECT_EQ(TopLabel({{"b", 1.0}, {"a", 1.0}}), "a");  // equal weights: the first alphabetically
  EXPECT_EQ(TopLabel({}), "");
  EXPECT_EQ(LabelDistribution({{"x", 0.0}}), (LabelWeights{{"x", 0.0}}));
}

}  // namespace
}  // namespace anchordb::engine

namespace anchordb::engine {
namespace events_labels_test {

TEST(EventsLabelsTest, FurnitureGoesByItsMostProbableNameFirstAlphabeticallyAmongEquals) {
  EXPECT_EQ(FurnitureName({}), "furniture");
  EXPECT_EQ(FurnitureName({{"table", 0.3}, {"chair", 0.7}}), "chair");
  EXPECT_EQ(FurnitureName({{"shelf", 0.5}, {"desk", 0.5}}), "desk");
  EXPECT_EQ(FurnitureName({{"sofa", 0.0}}), "sofa") << "a piece named with no weight still has that name";
}

}  // namespace
}  // namespace anchordb::engine
