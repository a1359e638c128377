// Seen-through removal (engine/events/rules.h JudgeSeenThrough; removed_min_seen_through, removed_min_visible_points):
// a later visit's view that sees through most of an object's known points proves it gone.
#include <gtest/gtest.h>

#include "engine/events/keyframe_analysis.h"
#include "engine/events/rules.h"
#include "tests/engine/events_test_support.h"

namespace anchordb::engine {
namespace events_seen_through_test {

Visibility Seen(int confirmed, int seen_through, int hidden = 0) {
  Visibility v;
  v.confirmed = confirmed;
  v.seen_through = seen_through;
  v.hidden = hidden;
  return v;
}

TEST(EventsSeenThroughTest, ThresholdsOfTheJudgement) {
  const auto judge = [](const Visibility& v) { return JudgeSeenThrough(v, kRemovedMinSeenThrough, kRemovedMinVisiblePoints); };
  EXPECT_EQ(judge(Seen(8, 12)), SeenThrough::kRemoved);     // 20 judged, 60 % seen through
  EXPECT_EQ(judge(Seen(9, 11)), SeenThrough::kUndecided);   // 55 %, and fewer than 20 confirmed
  EXPECT_EQ(judge(Seen(0, 19)), SeenThrough::kUndecided);   // too few points judged
  EXPECT_EQ(judge(Seen(25, 5)), SeenThrough::kSeenAgain);   // mostly confirmed
  EXPECT_EQ(judge(Seen(5, 0, 500)), SeenThrough::kUndecided);  // hidden points prove nothing
  EXPECT_EQ(JudgeSeenThrough(Seen(3, 3), 0.5, 6), SeenThrough::kRemoved);
}

// A camera at the map origin looking along +z at a wall 2 m away; an object known at 1.5 m.
constexpr int kW = 80, kH = 60;
const PinholeIntrinsics kK{kW, kH, 70.0, 70.0, 39.5, 29.5};

KnownInstance ObjectAt(std::int64_t id, double z_m) {
  KnownInstance k = testing::Instance(id, true, {0, 0, z_m}, {0.2, 0.2, 0.1});
  for (int i = 0; i < 64; ++i) k.sample_m.emplace_back(static_cast<float>(0.02 * (i % 8) - 0.07), static_cast<float>(0.02 * (i / 8) - 0.07), static_cast<float>(z_m));
  k.last_keyframe_id = 3;
  return k;
}

TEST(EventsSeenThroughTest, ABeginKeyframeThatSeesThroughAnObjectRemovesIt) {
  const std::vector<std::uint16_t> wall(kW * kH, 2000);
  BeginKeyframe k;
  k.keyframe_id = 8;
  k.scene_id = 4;
  k.stamp_ns = 5000;
  k.depth_mm = wall;
  k.K = kK;
  const ChangeSet c = AnalyseBeginKeyframe(k, {ObjectAt(1, 1.5)}, EventRules{});
  ASSERT_EQ(c.events.size(), 1u);
  const NewEvent& e = c.events[0];
  EXPECT_EQ(e.type, EventType::kRemoved);
  EXPECT_EQ(e.detection, Detection::kMeanwhile);
  EXPECT_EQ(e.visibility->seen_through, 64);
  EXPECT_EQ(e.evidence, (std::vector<Evidence>{{3, "before"}, {8, "after"}}));
  EXPECT_EQ(e.explanation, "the view now sees through 64 of 64 measured points of the object last seen at (0.00, 0.00, 1.50): "
                           "removed while the robot was away");
  ASSERT_EQ(c.updates.size(), 1u);
  EXPECT_EQ(c.updates[0].present, false);
  EXPECT_FALSE(c.updates[0].sample_m);  // the stored sample is kept
  ASSERT_EQ(c.history.size(), 1u);
  EXPECT_FALSE(c.history[0].present);
}

TEST(EventsSeenThroughTest, AnObjectStillThereIsSeenAgainWithoutAnEvent) {
  std::vector<std::uint16_t> depth(kW * kH, 2000);
  for (int v = 0; v < kH; ++v) for (int u = 20; u < 60; ++u) depth[v * kW + u] = 1500;
  BeginKeyframe k;
  k.stamp_ns = 5000;
  k.depth_mm = depth;
  k.K = kK;
  const ChangeSet c = AnalyseBeginKeyframe(k, {ObjectAt(1, 1.5)}, EventRules{});
  EXPECT_TRUE(c.events.empty());
  ASSERT_EQ(c.updates.size(), 1u);
  EXPECT_EQ(c.updates[0].last_seen_ns, 5000);
  EXPECT_FALSE(c.updates[0].touch);
}

}  // namespace
}  // namespace anchordb::engine
