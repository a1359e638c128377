// The frame journal of SceneService on a real SQLite file: one row per acknowledged frame, trimmed by checkpoints
// and by closing; bad frames leave no row; a second service on the same file (what a restarted server is) rebuilds a
// model from checkpoint plus journal with the layers of the first; a frame whose write fails is not kept in memory.
// The kill -9 cases against the real binary are in tests/http/scene_journal_http_test.cc.
#include "services/scene/scene_service.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/scene/depth_image.h"
#include "schema/error.h"
#include "services/grid/grid_service.h"
#include "storage/frame_journal.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace scene_journal_test {

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000LL;
const PinholeIntrinsics kK{64, 48, 60.0, 60.0, 31.5, 23.5};

// A wall 2 m ahead with a 20 x 20 px box at 1.5 m whose column shifts with `k` and seeded noise of +-3 mm.
std::vector<std::uint16_t> Depth(int k) {
  std::vector<std::uint16_t> mm(static_cast<std::size_t>(kK.width) * kK.height, 2000);
  std::uint32_t state = 12345u + static_cast<std::uint32_t>(k);
  for (auto& v : mm) {
    state = state * 1664525u + 1013904223u;
    v = static_cast<std::uint16_t>(v + static_cast<int>(state >> 29) - 3);
  }
  const int left = 10 + 2 * (k % 5);
  for (int v = 10; v < 30; ++v) for (int u = left; u < left + 20; ++u) mm[v * kK.width + u] = 1500;
  return mm;
}

class SceneJournalTest : public ::testing::Test {
 protected:
  SceneJournalTest() : clock_(kStartNs) {
    storage::StoreOptions so;
    so.path = dir_.File("scenes.sqlite");
    store_ = std::make_unique<storage::Store>(so);
    GridService(*store_, {}, {}).CreateMap({"home", "test"});
    limits_.persist_every_frames = 5;
    scenes_ = std::make_unique<SceneService>(*store_, limits_, MergeSettings{}, clock_);
  }
  std::int64_t Open() {
    OpenSceneRequest r;
    r.camera = kK;
    r.merge = false;
    return scenes_->Open("home", r).id;
  }
  // Frame k, as PNG or raw, with a dynamic mask on odd frames.
  FrameResult Add(SceneService& s, std::int64_t id, int k) {
    const std::vector<std::uint16_t> depth = Depth(k);
    const std::string png = engine::EncodeDepthPng(depth, kK.width, kK.height);
    const std::string raw(reinterpret_cast<const char*>(depth.data()), depth.size() * 2);
    std::vector<std::uint8_t> mask(depth.size(), 0);
    for (int v = 0; v < 8; ++v) for (int u = 50; u < 60; ++u) mask[v * kK.width + u] = 1;
    const std::string mask_png = engine::EncodeMaskPng(mask, kK.width, kK.height);
    FrameInput in;
    in.png = k % 2 == 0;
    in.body = in.png ? std::string_view(png) : std::string_view(raw);
    if (k % 2 == 1) in.dynamic_png = mask_png;
    in.stamp_ns = kStartNs + k * 33'000'000LL;
    return s.AddFrame("home", id, in);
  }
  std::int64_t Rows(std::int64_t id) {
    return store_->Read([&](storage::Connection& c) { return storage::CountJournalFrames(c, id); });
  }
  std::vector<std::string> Layers(SceneService& s, std::int64_t id) {
    std::vector<std::string> out;
    for (auto kind : {SceneLayerKind::kStatic, SceneLayerKind::kReliability, SceneLayerKind::kMovable, SceneLayerKind::kDynamic}) {
      out.push_back(s.Layer("home", id, kind, SceneLayerEncoding::kRaw, false).body);
    }
    return out;
  }

  testing::TempDir dir_;
  FakeClock clock_;
  SceneLimits limits_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<SceneService> scenes_;
};

TEST_F(SceneJournalTest, OneRowPerFrameTrimmedByCheckpointsAndGoneAtClose) {
  const std::int64_t id = Open();
  const std::vector<int> expected_rows = {1, 2, 3, 4, 1, 2, 3, 4, 5, 1, 2};  // checkpoints at 5 and 10 keep their last row
  for (int k = 1; k <= 11; ++k) {
    const FrameResult r = Add(*scenes_, id, k);
    EXPECT_EQ(r.frames, k);
    EXPECT_EQ(r.persisted_frames, k);
    EXPECT_EQ(Rows(id), expected_rows[k - 1]) << "after frame " << k;
  }
  const auto journal = store_->Read([&](storage::Connection& c) { return storage::ReadJournal(c, id, 0); });
  ASSERT_EQ(journal.size(), 2u);
  EXPECT_EQ(journal[0].frame, 10);
  EXPECT_EQ(journal[0].depth_codec, storage::JournalDepthCodec::kPng);
  EXPECT_FALSE(journal[0].dynamic_png);
  EXPECT_EQ(journal[1].frame, 11);
  EXPECT_EQ(journal[1].depth_codec, storage::JournalDepthCodec::kRawZstd);
  EXPECT_TRUE(journal[1].dynamic_png);
  EXPECT_EQ(journal[1].stamp_ns, kStartNs + 11 * 33'000'000LL);
  EXPECT_LT(journal[1].depth.size(), 64u * 48u * 2u) << "raw frames are journalled compressed";
  EXPECT_EQ(scenes_->Get("home", id).persisted_frames, 11);
  EXPECT_EQ(scenes_->List("home", {}).at(0).persisted_frames, 11);
  scenes_->Close("home", id);
  EXPECT_EQ(Rows(id), 0);
}

TEST_F(SceneJournalTest, BadFramesLeaveNoRow) {
  const std::int64_t id = Open();
  Add(*scenes_, id, 1);
  Add(*scenes_, id, 2);
  const std::vector<std::string> before = Layers(*scenes_, id);
  const std::vector<std::uint16_t> small(32 * 24, 1000);
  const std::string small_png = engine::EncodeDepthPng(small, 32, 24);
  const std::string truncated(100, '\0');
  const std::string png = engine::EncodeDepthPng(Depth(3), kK.width, kK.height);
  const std::string wrong_mask = engine::EncodeMaskPng(std::vector<std::uint8_t>(32 * 24, 1), 32, 24);
  std::vector<FrameInput> bad(5);
  bad[0].body = small_png;  // wrong size for the camera
  bad[1].body = truncated;
  bad[1].png = false;       // raw of the wrong length
  bad[2].body = "not a png";
  bad[3].body = png;
  bad[3].depth_scale = -1.0;
  bad[4].body = png;
  bad[4].dynamic_png = wrong_mask;
  for (const FrameInput& in : bad) {
    EXPECT_THROW(scenes_->AddFrame("home", id, in), Error);
    EXPECT_EQ(Rows(id), 2);
  }
  EXPECT_EQ(Layers(*scenes_, id), before);
  EXPECT_EQ(scenes_->Get("home", id).state->frames, 2);
  scenes_->Close("home", id);
  EXPECT_THROW(Add(*scenes_, id, 3), Error);  // closed
  EXPECT_EQ(Rows(id), 0);
}

TEST_F(SceneJournalTest, AnotherServiceOnTheFileRebuildsTheModelFromCheckpointAndJournal) {
  const std::int64_t id = Open();
  for (int k = 1; k <= 8; ++k) Add(*scenes_, id, k);  // a checkpoint at 5, three journalled frames after it
  const std::vector<std::string> layers = Layers(*scenes_, id);
  const SceneInfo info = scenes_->Get("home", id);
  // What a restarted server sees: the first service never persisted frames 6-8.
  SceneService restarted(*store_, limits_, MergeSettings{}, clock_);
  EXPECT_EQ(Layers(restarted, id), layers);
  const SceneInfo replayed = restarted.Get("home", id);
  EXPECT_EQ(replayed.state->frames, 8);
  EXPECT_EQ(replayed.persisted_frames, 8);
  EXPECT_EQ(replayed.last_frame_ns, info.last_frame_ns);
  EXPECT_EQ(replayed.keyframes.size(), info.keyframes.size()) << "no keyframe is made twice";
  // It continues as an uninterrupted model fed the same frames.
  const std::int64_t straight = Open();
  for (int k = 1; k <= 12; ++k) Add(*scenes_, straight, k);
  for (int k = 9; k <= 12; ++k) {
    const FrameResult a = Add(restarted, id, k);
    EXPECT_EQ(a.frames, k);
    EXPECT_EQ(a.persisted_frames, k);
  }
  EXPECT_EQ(Layers(restarted, id), Layers(*scenes_, straight));
  EXPECT_EQ(Rows(id), 3);  // checkpoint at 10 (its row kept), 11, 12
}

TEST_F(SceneJournalTest, AFrameWhoseWriteFailedIsNotKeptAndTheModelIsReloaded) {
  const std::int64_t id = Open();
  for (int k = 1; k <= 3; ++k) Add(*scenes_, id, k);
  // Another writer of the same file (a second server on it) journals frame 4 first: the first service's write of its
  // own frame 4 fails on the journal's key, and that frame must not stay in its memory.
  SceneService other(*store_, limits_, MergeSettings{}, clock_);
  EXPECT_EQ(Add(other, id, 4).frames, 4);
  EXPECT_THROW(Add(*scenes_, id, 7), Error);
  // The next request reloads the model from the database: it has frame 4 as the other service applied it.
  EXPECT_EQ(Layers(*scenes_, id), Layers(other, id));
  EXPECT_EQ(Add(*scenes_, id, 5).frames, 5);
  EXPECT_EQ(Rows(id), 1);  // frame 5 was a checkpoint
}

}  // namespace
}  // namespace anchordb::services
