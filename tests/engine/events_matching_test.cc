// Instance matching (engine/events/rules.h BestMatch on engine::MatchParams): a segment is the nearest instance
// whose position and size it fits, each instance at most once per keyframe.
#include <gtest/gtest.h>

#include "engine/events/keyframe_analysis.h"
#include "engine/events/rules.h"
#include "tests/engine/events_test_support.h"

namespace anchordb::engine {
namespace events_matching_test {

using testing::Box;
using testing::Instance;

const Eigen::Vector3d kMug(0.1, 0.1, 0.12);

TEST(EventsMatchingTest, TheNearestFittingInstanceNotTakenYet) {
  const std::vector<KnownInstance> instances = {Instance(1, true, {1.05, 0, 0.8}, kMug), Instance(2, true, {1.02, 0, 0.8}, kMug),
                                                Instance(3, true, {1.0, 0, 0.8}, {0.6, 0.6, 0.6})};  // far larger
  const Segment s = Box({1.0, 0, 0.8}, kMug);
  EXPECT_EQ(BestMatch(s, instances, {false, false, false}, MatchParams{}), 1);
  EXPECT_EQ(BestMatch(s, instances, {false, true, false}, MatchParams{}), 0);
  EXPECT_EQ(BestMatch(s, instances, {true, true, false}, MatchParams{}), -1);
  EXPECT_EQ(BestMatch(Box({1.5, 0, 0.8}, kMug), instances, {false, false, false}, MatchParams{}), -1);  // too far
  MatchParams loose;
  loose.min_size_ratio = 0.0;
  EXPECT_EQ(BestMatch(s, instances, {true, true, false}, loose), 2);
}

TEST(EventsMatchingTest, AMatchedSegmentConfirmsTheInstanceInsteadOfAnEvent) {
  KnownInstance mug = Instance(4, true, {1.0, 0, 0.8}, kMug);
  mug.last_seen_ns = 900;
  LayerKeyframe k = testing::Layer(11, 10, 700, 600, 2);
  k.added_segments = {Box({1.01, 0, 0.8}, kMug, 500, 5), Box({2.0, 0, 0.8}, kMug)};
  const ChangeSet c = AnalyseLayerKeyframe(k, {mug}, EventRules{});
  ASSERT_EQ(c.updates.size(), 1u);
  const InstanceUpdate& u = c.updates[0];
  EXPECT_EQ(u.instance, Ref::Existing(4));
  EXPECT_EQ(u.last_seen_ns, 900);  // never earlier than known
  EXPECT_EQ(u.last_scene_id, 2);
  EXPECT_EQ(u.sample_m->size(), 5u);
  EXPECT_FALSE(u.present);
  EXPECT_TRUE(u.touch);
  // The other segment is new: a new instance, its segment kept, an 'added' event observed in the layer.
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].type, EventType::kAdded);
  EXPECT_EQ(c.events[0].instance, Ref::New(0));
  EXPECT_EQ(c.events[0].segment, 0);
  EXPECT_EQ(c.segments.size(), 1u);
  EXPECT_EQ(c.segments[0].keyframe_id, 11);
  EXPECT_EQ(c.segments_examined, 2);
}

TEST(EventsMatchingTest, AnUnmatchedRemovalWasBackgroundAndBecomesAnAbsentInstance) {
  LayerKeyframe k = testing::Layer(11, 10, 700, 600, 2, 3);
  k.removed_segments = {Box({1.0, 0, 0.8}, kMug)};
  const ChangeSet c = AnalyseLayerKeyframe(k, {}, EventRules{});
  ASSERT_EQ(c.new_instances.size(), 1u);
  EXPECT_FALSE(c.new_instances[0].present);
  EXPECT_EQ(c.new_instances[0].last_seen_ns, 600);
  ASSERT_EQ(c.history.size(), 2u);  // there at the opening keyframe, gone at this one
  EXPECT_TRUE(c.history[0].present);
  EXPECT_EQ(c.history[0].stamp_ns, 600);
  EXPECT_FALSE(c.history[1].present);
  EXPECT_EQ(c.history[1].event, Ref::New(0));
  EXPECT_EQ(c.events[0].action_layer, 3);
  EXPECT_EQ(c.segments[0].keyframe_id, 10);  // the removed object shows in the opening keyframe's depth
}

TEST(EventsMatchingTest, ReanalysisKnowsSegmentsThatAnInstanceExplainedAtTheTime) {
  ReanalysedKeyframe k;
  k.keyframe_id = 5;
  k.scene_id = 1;
  k.stamp_ns = 1000;
  k.background_scene_id = 2;
  k.background_stamp_ns = 3000;
  k.background_keyframe_id = 9;
  k.segments = {Box({1.0, 0, 0.8}, kMug), Box({2.0, 0, 0.8}, kMug)};
  const std::vector<InstanceAtTime> instances = {{4, kMug, HistoryPoint{900, true, {1.0, 0, 0.8}, std::nullopt}},
                                                 {6, kMug, HistoryPoint{900, false, {2.0, 0, 0.8}, std::nullopt}}};
  const Reanalysis r = ReanalyseKeyframe(k, instances, MatchParams{});
  EXPECT_EQ(r.known_instance, (std::vector<std::optional<std::int64_t>>{4, std::nullopt}));
  ASSERT_EQ(r.changes.events.size(), 2u);  // the second: there then, gone now
  EXPECT_EQ(r.changes.events[0].type, EventType::kAdded);
  EXPECT_EQ(r.changes.events[0].detection, Detection::kReanalysis);
  EXPECT_EQ(r.changes.events[1].type, EventType::kRemoved);
  EXPECT_EQ(r.changes.events[1].stamp_ns, 3000);
  EXPECT_EQ(r.changes.events[1].evidence, (std::vector<Evidence>{{5, "before"}, {9, "after"}}));
  EXPECT_EQ(r.changes.events[1].background_scene, 2);
  EXPECT_EQ(r.changes.history.size(), 2u);
}

}  // namespace
}  // namespace anchordb::engine
