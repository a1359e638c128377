#include "engine/classification/object_labels.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace classification_object_labels_test {

TEST(ObjectLabelsTest, APersonsLabelAlwaysWinsOverTheClassifier) {
  const LabelWeights classified = {{"cup", 0.75}, {"box", 0.25}};
  // Nobody named it: the classifier's distribution is its label.
  EffectiveLabels none = EffectiveObjectLabels({}, false, classified);
  EXPECT_EQ(none.source, LabelSource::kClassifier);
  EXPECT_DOUBLE_EQ(none.distribution.at("cup"), 0.75);
  EXPECT_TRUE(ClassifierLabelApplies({}, false));
  // Dialog named it: dialog's distribution, whatever the classifier says.
  EffectiveLabels dialog = EffectiveObjectLabels({{"keys", 2.0}, {"wallet", 2.0}}, false, classified);
  EXPECT_EQ(dialog.source, LabelSource::kDialog);
  EXPECT_EQ(dialog.distribution, (LabelWeights{{"keys", 0.5}, {"wallet", 0.5}}));
  EXPECT_FALSE(ClassifierLabelApplies({{"keys", 1.0}}, false));
  // An operator's label (locked).
  EffectiveLabels op = EffectiveObjectLabels({{"mug", 1.0}}, true, classified);
  EXPECT_EQ(op.source, LabelSource::kOperator);
  EXPECT_EQ(op.distribution, (LabelWeights{{"mug", 1.0}}));
  EXPECT_FALSE(ClassifierLabelApplies({}, true));
  // No classification and no name.
  EXPECT_EQ(EffectiveObjectLabels({}, false, std::nullopt).source, LabelSource::kNone);
  EXPECT_STREQ(LabelSourceName(LabelSource::kClassifier), "classifier");
}

TEST(ObjectLabelsTest, ClassesOfNoShareAndTheUnknownClassAreNoLabel) {
  const EffectiveLabels e = EffectiveObjectLabels({}, false, LabelWeights{{"cup", 0.6}, {"box", 0.0}, {"unknown", 0.4}});
  EXPECT_EQ(e.source, LabelSource::kClassifier);
  EXPECT_EQ(e.distribution, (LabelWeights{{"cup", 1.0}}));
  EXPECT_EQ(EffectiveObjectLabels({}, false, LabelWeights{{"unknown", 1.0}}).source, LabelSource::kNone);
}

TEST(ObjectLabelsTest, PointsInsideTheSegmentBoxWithItsMargin) {
  const std::vector<Eigen::Vector3f> cloud = {{0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 0.5f}, {1.005f, 0.5f, 0.5f}, {1.2f, 0.5f, 0.5f}};
  EXPECT_EQ(PointsInBox(cloud, {0, 0, 0}, {1, 1, 1}, 0.0).size(), 2u);
  EXPECT_EQ(PointsInBox(cloud, {0, 0, 0}, {1, 1, 1}, 0.01).size(), 3u);
  EXPECT_TRUE(PointsInBox(cloud, {1, 1, 1}, {0, 0, 0}, 0.01).empty());  // inverted
  EXPECT_TRUE(PointsInBox(cloud, {0, 0, 0}, {1, 1, 1}, -0.1).empty());
}

}  // namespace
}  // namespace anchordb::engine
