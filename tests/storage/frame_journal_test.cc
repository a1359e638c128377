// The frame journal repository on a real SQLite file: append, read back across a reopen, trim, the (scene, frame)
// key, and the rows going with their scene model and their map (foreign keys).
#include "storage/frame_journal.h"

#include <gtest/gtest.h>

#include <tuple>

#include "schema/error.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace frame_journal_test {

std::int64_t AddScene(Store& store, const std::string& map) {
  return store.Write([&](Connection& c) {
    if (!FindMap(c, map)) InsertMap(c, {map, map, 1});
    SceneRecord r;
    r.map_id = map;
    return InsertScene(c, r);
  });
}

JournalFrame Frame(std::int64_t scene, std::int64_t frame, bool png) {
  JournalFrame f;
  f.scene_id = scene;
  f.frame = frame;
  f.stamp_ns = 1000 + frame;
  f.depth_codec = png ? JournalDepthCodec::kPng : JournalDepthCodec::kRawZstd;
  f.depth = std::string("depth\0of frame ", 15) + std::to_string(frame);  // bytes, NULs included
  f.depth_scale = png ? 1000.0 : 5000.0;
  if (frame % 2 == 0) f.dynamic_png = "mask " + std::to_string(frame);
  f.model_after = {100 + frame, 2, 3 * frame, 4, 5, 6, 7, frame == 1 ? -1 : frame, frame % 4};
  return f;
}

void ExpectSame(const JournalFrame& a, const JournalFrame& b) {
  EXPECT_EQ(a.scene_id, b.scene_id);
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.stamp_ns, b.stamp_ns);
  EXPECT_EQ(a.depth_codec, b.depth_codec);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.depth_scale, b.depth_scale);
  EXPECT_EQ(a.dynamic_png, b.dynamic_png);
  const JournalModelAfter& x = a.model_after;
  const JournalModelAfter& y = b.model_after;
  EXPECT_EQ(std::tie(x.supported_px, x.reset_px, x.movable_px, x.dynamic_px, x.no_depth_px,
                     x.settle_movable_at_keyframe_px, x.settle_reset_since_keyframe_px, x.settle_previous_movable_px,
                     x.settle_stable_frames),
            std::tie(y.supported_px, y.reset_px, y.movable_px, y.dynamic_px, y.no_depth_px,
                     y.settle_movable_at_keyframe_px, y.settle_reset_since_keyframe_px, y.settle_previous_movable_px,
                     y.settle_stable_frames));
}

class FrameJournalTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, FrameJournalTest, testing::BothEngines(), testing::EngineName);

TEST_P(FrameJournalTest, AppendReadBackAcrossReopenTrimAndDelete) {
  const std::string path = db_.location();
  std::int64_t scene = 0, other = 0;
  {
    Store store(StoreOptions{path});
    scene = AddScene(store, "home");
    other = AddScene(store, "home");
    for (int k = 1; k <= 5; ++k) store.Write([&](Connection& c) { AppendJournalFrame(c, Frame(scene, k, k % 3 != 0)); });
    store.Write([&](Connection& c) { AppendJournalFrame(c, Frame(other, 1, true)); });
  }
  Store store(StoreOptions{path});
  auto read = [&](std::int64_t id, std::int64_t from) { return store.Read([&](Connection& c) { return ReadJournal(c, id, from); }); };
  const auto all = read(scene, 0);
  ASSERT_EQ(all.size(), 5u);
  for (int k = 1; k <= 5; ++k) ExpectSame(all[k - 1], Frame(scene, k, k % 3 != 0));
  EXPECT_EQ(read(scene, 4).size(), 2u);
  EXPECT_EQ(read(scene, 4).front().frame, 4);
  const auto tail = store.Read([&](Connection& c) { return LastJournalFrame(c, scene); });
  ASSERT_TRUE(tail);
  EXPECT_EQ(tail->frame, 5);
  EXPECT_EQ(tail->stamp_ns, 1005);

  // A frame is journalled once.
  try {
    store.Write([&](Connection& c) { AppendJournalFrame(c, Frame(scene, 3, true)); });
    ADD_FAILURE() << "a second row for frame 3 was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kConflict) << e.what();
  }
  // The model_after of a row is replaced in place; a missing row says so.
  JournalModelAfter after_keyframe = Frame(scene, 5, true).model_after;
  after_keyframe.settle_movable_at_keyframe_px = 4321;
  after_keyframe.settle_stable_frames = 0;
  EXPECT_TRUE(store.Write([&](Connection& c) { return UpdateJournalModelAfter(c, scene, 5, after_keyframe); }));
  EXPECT_FALSE(store.Write([&](Connection& c) { return UpdateJournalModelAfter(c, scene, 9, after_keyframe); }));
  EXPECT_EQ(read(scene, 5).front().model_after.settle_movable_at_keyframe_px, 4321);
  EXPECT_EQ(read(scene, 5).front().model_after.settle_stable_frames, 0);
  EXPECT_EQ(read(scene, 5).front().model_after.supported_px, 105);

  // A checkpoint of 4 frames keeps the row of its last frame and those after it; the other scene is untouched.
  EXPECT_EQ(store.Write([&](Connection& c) { return TrimJournal(c, scene, 4); }), 3);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c, scene); }), 2);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c, other); }), 1);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c); }), 3);
  EXPECT_EQ(store.Write([&](Connection& c) { return DeleteJournal(c, scene); }), 2);
  EXPECT_FALSE(store.Read([&](Connection& c) { return LastJournalFrame(c, scene); }));
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c); }), 1);
}

TEST_P(FrameJournalTest, RowsGoWithTheirSceneModelAndTheirMap) {
  Store store(StoreOptions{db_.location()});
  const std::int64_t a = AddScene(store, "home");
  const std::int64_t b = AddScene(store, "home");
  const std::int64_t c_other = AddScene(store, "office");
  for (std::int64_t id : {a, b, c_other}) {
    store.Write([&](Connection& c) {
      for (int k = 1; k <= 3; ++k) AppendJournalFrame(c, Frame(id, k, true));
    });
  }
  // A scene model deleted (as forgetting deletes superseded ones) takes its rows with it.
  store.Write([&](Connection& c) { Statement(c, "DELETE FROM scene_models WHERE id = ?").Bind(1, a).Run(); });
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c, a); }), 0);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c); }), 6);
  // A deleted map takes its models' rows.
  EXPECT_TRUE(store.Write([&](Connection& c) { return DeleteMap(c, "home"); }));
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c, b); }), 0);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c); }), 3);
  // A row for a scene model that does not exist is refused.
  EXPECT_THROW(store.Write([&](Connection& c) { AppendJournalFrame(c, Frame(999, 1, true)); }), Error);
  EXPECT_EQ(store.Read([&](Connection& c) { return CountJournalFrames(c); }), 3);
}

}  // namespace
}  // namespace anchordb::storage
