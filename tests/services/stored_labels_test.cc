// The one codec of an instance's stored labels (services/common/stored_labels.h): what it writes reads back, the
// lenient read leaves out what is not a weight, and the strict read refuses text that is not an object with
// kInternal naming the row.
#include "services/common/stored_labels.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::services {
namespace {

TEST(StoredLabelsTest, WrittenWeightsReadBackExactly) {
  const engine::LabelWeights weights{{"keys", 0.75}, {"wallet", 0.1 + 0.2}, {"chair \"big\"", 1e-300}};
  const auto back = ReadLabelWeights(EncodeLabelWeights(weights));
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, weights);
  EXPECT_EQ(DecodeLabelWeights(EncodeLabelWeights({}), "row"), engine::LabelWeights{});
}

TEST(StoredLabelsTest, TheLenientReadLeavesOutWhatIsNotAWeight) {
  const auto read = ReadLabelWeights(R"({"cup": 2, "note": "x", "flag": true, "nested": {"a": 1}, "none": null})");
  ASSERT_TRUE(read);
  EXPECT_EQ(*read, (engine::LabelWeights{{"cup", 2.0}}));
  EXPECT_FALSE(ReadLabelWeights("[1, 2]"));
  EXPECT_FALSE(ReadLabelWeights("{\"cup\": "));
  EXPECT_FALSE(ReadLabelWeights(""));
}

TEST(StoredLabelsTest, TheStrictReadRefusesTextThatIsNotAnObjectNamingTheRow) {
  try {
    DecodeLabelWeights("\"keys\"", "instance 42");
    ADD_FAILURE() << "a string was read as labels";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    EXPECT_NE(std::string(e.what()).find("instance 42"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace anchordb::services
