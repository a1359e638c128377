// Label ids of label layers (engine/grid/labels.h): a name keeps its id, a new name gets the highest id + 1.
#include "engine/grid/labels.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "tests/support/test_grids.h"

namespace anchordb::engine {
namespace grid_label_ids_test {

TEST(GridLabelIds, AKnownNameKeepsItsId) {
  const LabelIdChoice c = ChooseLabelId({{1, "hall"}, {4, "kitchen"}}, "kitchen");
  EXPECT_EQ(c.id, 4);
  EXPECT_FALSE(c.is_new);
}

TEST(GridLabelIds, ANewNameGetsOneAboveTheHighestId) {
  EXPECT_EQ(ChooseLabelId({}, "hall").id, 1);
  const LabelIdChoice c = ChooseLabelId({{2, "hall"}, {9, "bath"}}, "kitchen");
  EXPECT_EQ(c.id, 10);
  EXPECT_TRUE(c.is_new);
}

TEST(GridLabelIds, OfDuplicateNamesTheIdWhoseTextSortsLastWins) {
  // The stored table is a JSON object: "10" < "2" < "3"; the name's last id in that order is used.
  EXPECT_EQ(ChooseLabelId({{2, "hall"}, {3, "bath"}, {10, "hall"}}, "hall").id, 2);
}

TEST(GridLabelIds, NoIdBeyond65535) {
  EXPECT_EQ(ChooseLabelId({{65535, "last"}}, "last").id, 65535);
  try {
    ChooseLabelId({{65535, "last"}}, "one more");
    FAIL() << "expected kUnprocessable";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnprocessable);
    EXPECT_EQ(e.field(), "label");
  }
}

TEST(GridLabelIds, PaintMaskWritesTheIdUnderTheMaskOnly) {
  LabelGrid labels(testing::FreeGrid(4, 1, 1.0).geometry, 0);
  labels.cells = {3, 3, 0, 0};
  MaskGrid mask(labels.geometry, 0);
  mask.cells = {0, 1, 1, 0};
  PaintMask(mask, 7, labels);
  EXPECT_EQ(labels.cells, (std::vector<std::uint16_t>{3, 7, 7, 0}));
}

}  // namespace
}  // namespace anchordb::engine
