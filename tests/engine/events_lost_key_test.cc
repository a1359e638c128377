// The lost-key rule (thesis 3.3.4): a labelled removal continued by an observed, unlabelled addition of compatible
// size is a move (engine/events/rules.h LostKeyMove, keyframe_analysis.h AnalyseLayerKeyframe).
#include <gtest/gtest.h>

#include "engine/events/keyframe_analysis.h"
#include "engine/events/rules.h"
#include "tests/engine/events_test_support.h"

namespace anchordb::engine {
namespace events_lost_key_test {

using testing::Box;
using testing::Instance;
using testing::Removed;

const Eigen::Vector3d kKeysExtent(0.08, 0.05, 0.03);

TEST(EventsLostKeyTest, AnAdditionOfCompatibleSizeContinuesTheLabelledRemoval) {
  const std::vector<KnownInstance> instances = {Removed(7, "keys", {0.0, 3.0, 0.9}, kKeysExtent, 100)};
  const auto move = LostKeyMove({0.07, 0.05, 0.03}, instances, 200, kMoveMinSizeSimilarity);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->index, 0);
  EXPECT_NEAR(move->size_similarity, SizeSimilarity(kKeysExtent, {0.07, 0.05, 0.03}), 1e-12);
  // Removed at the same time as the addition still counts (taken and put down within one action layer).
  EXPECT_TRUE(LostKeyMove(kKeysExtent, instances, 100, kMoveMinSizeSimilarity));
}

TEST(EventsLostKeyTest, NoMoveForUnlabelledLockedLaterOrDifferentlySizedRemovals) {
  KnownInstance unlabelled = Removed(1, "x", {0, 0, 0}, kKeysExtent, 100);
  unlabelled.labels.clear();
  KnownInstance locked = Removed(2, "keys", {0, 0, 0}, kKeysExtent, 100);
  locked.status_locked = true;
  const KnownInstance later = Removed(3, "keys", {0, 0, 0}, kKeysExtent, 300);  // removed after the addition
  KnownInstance seen_again = Removed(4, "keys", {0, 0, 0}, kKeysExtent, 100);
  seen_again.last_history->present = true;  // its newest history row is a presence
  const KnownInstance present = Instance(5, true, {0, 0, 0}, kKeysExtent);
  KnownInstance no_history = Removed(6, "keys", {0, 0, 0}, kKeysExtent, 100);
  no_history.last_history.reset();
  EXPECT_FALSE(LostKeyMove(kKeysExtent, {unlabelled, locked, later, seen_again, present, no_history}, 200, kMoveMinSizeSimilarity));
  // A book (flat and large) is not the keys.
  EXPECT_FALSE(LostKeyMove({0.3, 0.2, 0.02}, {Removed(8, "keys", {0, 0, 0}, kKeysExtent, 100)}, 200, kMoveMinSizeSimilarity));
}

TEST(EventsLostKeyTest, TheMostSimilarRemovalWinsAndTheLaterOneAmongEquals) {
  const std::vector<KnownInstance> instances = {Removed(1, "mug", {0, 0, 0}, {0.1, 0.1, 0.12}, 100),
                                                Removed(2, "keys", {1, 0, 0}, kKeysExtent, 100),
                                                Removed(3, "wallet", {2, 0, 0}, kKeysExtent, 100)};
  const auto move = LostKeyMove(kKeysExtent, instances, 200, kMoveMinSizeSimilarity);
  ASSERT_TRUE(move);
  EXPECT_EQ(move->index, 2);
  EXPECT_NEAR(move->size_similarity, 1.0, 1e-12);
  EXPECT_EQ(LostKeyMove({0.1, 0.1, 0.12}, instances, 200, kMoveMinSizeSimilarity)->index, 0);
}

TEST(EventsLostKeyTest, LayerAnalysisInfersTheMoveAndExplainsIt) {
  LayerKeyframe k = testing::Layer(20, 19, 500, 400, 3, 1);
  k.added_segments = {Box({2.3, 0.1, 0.8}, {0.07, 0.05, 0.03})};
  const ChangeSet c = AnalyseLayerKeyframe(k, {Removed(7, "keys", {0.0, 3.0, 0.9}, kKeysExtent, 300, 41)}, EventRules{});
  ASSERT_EQ(c.events.size(), 1u);
  const NewEvent& e = c.events[0];
  EXPECT_EQ(e.type, EventType::kMoved);
  EXPECT_EQ(e.detection, Detection::kObserved);
  EXPECT_EQ(e.instance, Ref::Existing(7));
  EXPECT_EQ(e.label, "keys");
  ASSERT_TRUE(e.move);
  EXPECT_EQ(e.move->removal_event, Ref::Existing(41));
  EXPECT_EQ(e.move->from_m, Eigen::Vector3d(0.0, 3.0, 0.9));
  EXPECT_EQ(e.explanation.rfind("inferred move (lost-key rule, thesis 3.3.4): 'keys' (instance 7) was removed from "
                                "(0.00, 3.00, 0.90)", 0), 0u) << e.explanation;
  EXPECT_EQ(e.evidence, (std::vector<Evidence>{{19, "before"}, {20, "after"}}));
  EXPECT_TRUE(c.new_instances.empty());
  ASSERT_EQ(c.updates.size(), 1u);
  EXPECT_EQ(c.updates[0].present, true);
  EXPECT_EQ(c.updates[0].position_m, Eigen::Vector3d(2.3, 0.1, 0.8));
  ASSERT_EQ(c.history.size(), 1u);
  EXPECT_TRUE(c.history[0].present);
  EXPECT_EQ(c.history[0].event, Ref::New(0));
}

TEST(EventsLostKeyTest, ARemovalAndAnAdditionInOneLayerAreAMoveOfThatObject) {
  KnownInstance keys = Instance(7, true, {0.0, 3.0, 0.9}, kKeysExtent);
  keys.labels = {{"keys", 2.0}, {"key", 1.0}};
  LayerKeyframe k = testing::Layer(20, 19, 500, 400);
  k.removed_segments = {Box({0.0, 3.0, 0.9}, kKeysExtent)};
  k.added_segments = {Box({2.3, 0.1, 0.8}, kKeysExtent)};
  const ChangeSet c = AnalyseLayerKeyframe(k, {keys}, EventRules{});
  ASSERT_EQ(c.events.size(), 2u);
  EXPECT_EQ(c.events[0].type, EventType::kRemoved);
  EXPECT_EQ(c.events[1].type, EventType::kMoved);
  EXPECT_EQ(c.events[1].label, "keys");
  EXPECT_EQ(c.events[1].move->removal_event, Ref::New(0));  // the removal of this change set
  EXPECT_EQ(c.segments.size(), 2u);
  EXPECT_EQ(c.segments_examined, 2);
}

TEST(EventsLostKeyTest, OnlyObservedAdditionsContinueARemoval) {
  BeginKeyframe k;  // a later visit: what appeared meanwhile was not seen being brought
  k.keyframe_id = 30;
  k.front_segments = {Box({2.3, 0.1, 0.8}, kKeysExtent)};
  const ChangeSet c = AnalyseBeginKeyframe(k, {Removed(7, "keys", {0.0, 3.0, 0.9}, kKeysExtent, 300)}, EventRules{});
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].type, EventType::kAdded);
  EXPECT_EQ(c.events[0].detection, Detection::kMeanwhile);
  EXPECT_EQ(c.new_instances.size(), 1u);
}

}  // namespace
}  // namespace anchordb::engine
