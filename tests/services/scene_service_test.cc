// SceneService without HTTP, on a fake clock: typed open/frames/keyframes/close, a settled movement, the merge with
// supersession (also with two models merging the same earlier one at once), bad values refused, and the stored
// documents read back as written.
#include "services/scene/scene_service.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "engine/scene/depth_image.h"
#include "schema/error.h"
#include "services/grid/grid_service.h"
#include "services/scene/scene_stored_documents.h"
#include "storage/connection.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace scene_service_test {

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000LL;
const PinholeIntrinsics kK{64, 48, 60.0, 60.0, 31.5, 23.5};

// The corner of a room (a wall 2 m ahead, a side wall 0.6 m right, the floor 0.5 m below the camera, in the optical
// frame), optionally with a 20 x 20 px box at 1.5 m in front of the wall (400 px). Three planes: ICP is determined
// (on a single plane it is not).
std::string Frame(bool box) {
  std::vector<std::uint16_t> mm(static_cast<std::size_t>(kK.width) * kK.height);
  for (int v = 0; v < kK.height; ++v) {
    for (int u = 0; u < kK.width; ++u) {
      const double dx = (u - kK.cx) / kK.fx, dy = (v - kK.cy) / kK.fy;
      double z = 2.0;
      if (dx > 0) z = std::min(z, 0.6 / dx);
      if (dy > 0) z = std::min(z, 0.5 / dy);
      mm[v * kK.width + u] = static_cast<std::uint16_t>(std::lround(z * 1000.0));
    }
  }
  if (box) {
    for (int v = 10; v < 30; ++v) for (int u = 20; u < 40; ++u) mm[v * kK.width + u] = 1500;
  }
  return engine::EncodeDepthPng(mm, kK.width, kK.height);
}

class SceneServiceTest : public ::testing::Test {
 protected:
  SceneServiceTest() : clock_(kStartNs) {
    storage::StoreOptions so;
    so.path = dir_.File("scenes.sqlite");
    store_ = std::make_unique<storage::Store>(so);
    GridService(*store_, {}, {}).CreateMap({"home", "test"});
    scenes_ = std::make_unique<SceneService>(*store_, SceneLimits{}, MergeSettings{}, clock_);
  }
  OpenSceneRequest At(const Eigen::Vector3d& p) const {
    OpenSceneRequest r;
    r.camera = kK;
    r.X_MapCamera.position_m = p;
    return r;
  }
  FrameResult Add(std::int64_t id, const std::string& png) {
    FrameInput in;
    in.body = png;
    return scenes_->AddFrame("home", id, in);
  }
  std::int64_t Observed(const Eigen::Vector3d& p, int frames) {
    const std::int64_t id = scenes_->Open("home", At(p)).id;
    const std::string wall = Frame(false);
    for (int i = 0; i < frames; ++i) Add(id, wall);
    scenes_->Close("home", id);
    return id;
  }

  testing::TempDir dir_;
  FakeClock clock_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<SceneService> scenes_;
};

ErrorCode CodeOf(const std::function<void()>& f, std::string* field = nullptr) {
  try {
    f();
  } catch (const Error& e) {
    if (field) *field = e.field();
    return e.code();
  }
  return ErrorCode::kInternal;
}

TEST_F(SceneServiceTest, StampsComeFromTheInjectedClock) {
  const SceneInfo opened = scenes_->Open("home", At({0, 0, 1}));
  EXPECT_EQ(opened.started_ns, kStartNs);
  EXPECT_EQ(opened.status, SceneStatus::kObserving);
  ASSERT_TRUE(opened.state);
  EXPECT_EQ(opened.state->frames, 0);
  EXPECT_FALSE(opened.merge.pending.value_or(true));  // nothing earlier to merge
  clock_.AdvanceNs(5'000'000);
  const FrameResult first = Add(opened.id, Frame(false));
  ASSERT_TRUE(first.keyframe);
  EXPECT_EQ(first.keyframe->kind, KeyframeKind::kBegin);
  EXPECT_FALSE(first.keyframe->analysis);  // no listener
  EXPECT_EQ(first.pixels.reset, static_cast<std::size_t>(kK.width * kK.height));
  clock_.AdvanceNs(5'000'000);
  const KeyframeResult manual = scenes_->Keyframe("home", opened.id);
  EXPECT_EQ(manual.keyframe.action_layer, 1);
  const CloseResult closed = scenes_->Close("home", opened.id);
  EXPECT_EQ(closed.frames, 1);
  const SceneInfo info = scenes_->Get("home", opened.id);
  EXPECT_EQ(info.last_frame_ns, kStartNs + 5'000'000);  // the frame's time
  EXPECT_EQ(info.ended_ns, kStartNs + 5'000'000);       // the last frame's, not the clock's
  ASSERT_EQ(info.keyframes.size(), 3u);
  EXPECT_EQ(scenes_->GetKeyframe("home", info.keyframes[1].id).stamp_ns, kStartNs + 5'000'000);
}

TEST_F(SceneServiceTest, ACompletedMovementStoresASettledKeyframe) {
  const std::int64_t id = scenes_->Open("home", At({0, 0, 1})).id;
  const std::string wall = Frame(false), box = Frame(true);
  for (int i = 0; i < 3; ++i) Add(id, wall);
  EXPECT_EQ(Add(id, box).pixels.movable, 400u);  // the movement: not yet settled
  std::vector<int> settled_at;
  for (int i = 1; i <= 12; ++i) {
    const FrameResult r = Add(id, box);
    if (r.keyframe) {
      EXPECT_EQ(r.keyframe->kind, KeyframeKind::kSettled);
      settled_at.push_back(i);
    }
  }
  EXPECT_EQ(settled_at, std::vector<int>{8});  // settle_frames steady frames, once
}

TEST_F(SceneServiceTest, AReopenedViewpointMergesAndSupersedesTheEarlierModel) {
  const std::int64_t a = Observed({0, 0, 1}, 3);
  const SceneInfo b = scenes_->Open("home", At({0, 0, 1}));
  ASSERT_EQ(b.merge.candidates.size(), 1u);
  EXPECT_EQ(b.merge.candidates[0].id, a);
  EXPECT_TRUE(b.merge.pending.value_or(false));
  Add(b.id, Frame(false));
  const SceneInfo merged = scenes_->Get("home", b.id);
  EXPECT_TRUE(merged.merge.performed);
  EXPECT_FALSE(*merged.merge.pending);
  ASSERT_EQ(merged.merge.models_used.size(), 1u);
  EXPECT_EQ(merged.merge.superseded, std::vector<std::int64_t>{a});
  const SceneInfo old = scenes_->Get("home", a);
  EXPECT_EQ(old.status, SceneStatus::kSuperseded);
  EXPECT_EQ(old.superseded_by, b.id);
  // Older than max_age_s: not a candidate.
  clock_.AdvanceNs(static_cast<std::int64_t>(MergeSettings{}.max_age_s * 1e9) + 1);
  EXPECT_TRUE(scenes_->Open("home", At({0, 0, 1})).merge.candidates.empty());
}

// Two new models merge the same earlier one at once: each merge runs outside the write lock and commits only if the
// earlier model is still as it read it; the one that finds it changed merges again. Both succeed in any order.
TEST_F(SceneServiceTest, ConcurrentMergesOfOneEarlierModelBothCommit) {
  const std::int64_t a = Observed({0, 0, 1}, 3);
  const std::int64_t b = scenes_->Open("home", At({0, 0, 1})).id;
  const std::int64_t c = scenes_->Open("home", At({0, 0, 1})).id;
  const std::string wall = Frame(false);
  std::thread other([&] { Add(c, wall); });
  Add(b, wall);
  other.join();
  for (std::int64_t id : {b, c}) {
    const SceneInfo s = scenes_->Get("home", id);
    EXPECT_TRUE(s.merge.performed) << id;
    EXPECT_EQ(s.merge.superseded, std::vector<std::int64_t>{a}) << id;
  }
  const SceneInfo old = scenes_->Get("home", a);
  EXPECT_EQ(old.status, SceneStatus::kSuperseded);
  EXPECT_TRUE(old.superseded_by == b || old.superseded_by == c);
}

TEST_F(SceneServiceTest, BadValuesAreRefusedWithTheirField) {
  std::string field;
  OpenSceneRequest r = At({0, 0, 1});
  r.camera.width = 5000;
  EXPECT_EQ(CodeOf([&] { scenes_->Open("home", r); }, &field), ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "camera.width");
  r = At({0, 0, 1});
  r.camera.fy = 0;
  EXPECT_EQ(CodeOf([&] { scenes_->Open("home", r); }, &field), ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "camera.fx");
  r = At({0, 0, 1});
  r.params.model.beta = 1.5;
  EXPECT_EQ(CodeOf([&] { scenes_->Open("home", r); }, &field), ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "params.beta");
  r = At({0, 0, 1});
  r.params.depth_scale = 0;
  EXPECT_EQ(CodeOf([&] { scenes_->Open("home", r); }, &field), ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "params.depth_scale");
  EXPECT_EQ(CodeOf([&] { scenes_->Open("nowhere", At({0, 0, 1})); }, &field), ErrorCode::kNotFound);
  EXPECT_TRUE(scenes_->List("home", {}).empty());
  const std::int64_t id = scenes_->Open("home", At({0, 0, 1})).id;
  EXPECT_EQ(CodeOf([&] { scenes_->Keyframe("home", id); }), ErrorCode::kConflict);  // no frame yet
  EXPECT_EQ(CodeOf([&] { scenes_->Layer("home", id, SceneLayerKind::kStatic, SceneLayerEncoding::kPng, true); }, &field),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(field, "clean");
  FrameInput in;
  const std::string png = Frame(false);
  in.body = png;
  in.depth_scale = -1;
  EXPECT_EQ(CodeOf([&] { scenes_->AddFrame("home", id, in); }, &field), ErrorCode::kUnprocessable);
  EXPECT_EQ(field, "depth_scale");
  scenes_->Close("home", id);
  EXPECT_EQ(CodeOf([&] { Add(id, png); }), ErrorCode::kConflict);
}

TEST_F(SceneServiceTest, LayersAndListsAreTyped) {
  const std::int64_t id = Observed({0, 0, 1}, 2);
  const SceneLayerSummary s = scenes_->LayerSummary("home", id, SceneLayerKind::kStatic, false);
  EXPECT_EQ(s.pixels, static_cast<std::size_t>(kK.width * kK.height));
  EXPECT_GT(s.mean_depth_m, 1.5);
  EXPECT_LT(s.mean_depth_m, 2.0);
  const ExportedLayer raw = scenes_->Layer("home", id, SceneLayerKind::kStatic, SceneLayerEncoding::kRaw, false);
  EXPECT_EQ(raw.body.size(), 4u * kK.width * kK.height);
  EXPECT_EQ(raw.element, RawElement::kF32Metres);
  SceneListFilter near;
  near.near_m = Eigen::Vector3d(0, 0, 1);
  near.status = SceneStatus::kClosed;
  const auto listed = scenes_->List("home", near);
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].id, id);
  EXPECT_FALSE(listed[0].state);  // List does not load states
  near.near_m = Eigen::Vector3d(3, 0, 1);
  EXPECT_TRUE(scenes_->List("home", near).empty());
}

// The merge report maps to the store's record and back unchanged, NaN included (the responses show it as stored).
TEST(SceneStoredDocumentsTest, MergeReportRoundTripsThroughItsStoredRecord) {
  MergeReport r;
  r.requested = true;
  r.strategy = engine::MergeStrategy::kNaive;
  r.candidates = {{3, 0.8125}, {5, 0.25}};
  r.pending = false;
  r.performed = true;
  MergedModel m;
  m.scene_id = 3;
  m.icp_converged = true;
  m.fitness_m2 = std::nan("");
  m.fitness_before_m2 = 0.0123;
  m.correction_translation_m = {0.01, -0.02, 0.003};
  m.correction_rotation_rad = 0.0174;
  m.source_points = 1200;
  m.icp_verdict = "applied";
  m.relative_information = {1, 0.9, 0.8, 0.7, 0.6, 0.5};
  m.unobservable_directions = 1;
  m.remaining_sigma = {0.01, 0.02, 0.03, 0.001, 0.002, 0.003};
  m.rasterised = 10;
  m.rejected_uncertain = 2;
  m.tolerance_px = 1.5;
  m.fallback = "";
  r.models_used = {m};
  r.timing = {103.7, 5.0, 14.3};
  r.superseded = {3};
  Pose3 corrected;
  corrected.position_m = {0.1, 0.2, 1.3};
  corrected.orientation = Eigen::Quaterniond(0.9987502603949663, 0.0, 0.0, 0.0499791692706783);
  r.X_MapCamera_corrected = corrected;
  r.corrected_by_scene = 3;
  const MergeReport back = scene_stored::DecodeMergeReport(scene_stored::EncodeMergeReport(r), 7);
  EXPECT_EQ(back.strategy, engine::MergeStrategy::kNaive);
  ASSERT_EQ(back.candidates.size(), 2u);
  EXPECT_EQ(back.candidates[1].id, 5);
  EXPECT_EQ(back.pending, std::optional<bool>(false));
  ASSERT_EQ(back.models_used.size(), 1u);
  EXPECT_TRUE(std::isnan(back.models_used[0].fitness_m2));
  EXPECT_EQ(back.models_used[0].correction_translation_m, m.correction_translation_m);
  EXPECT_EQ(back.models_used[0].relative_information, m.relative_information);
  EXPECT_EQ(back.models_used[0].remaining_sigma, m.remaining_sigma);
  EXPECT_EQ(back.models_used[0].rejected_uncertain, 2u);
  EXPECT_EQ(back.models_used[0].icp_verdict, "applied");
  EXPECT_EQ(back.timing.icp_ms, 103.7);
  EXPECT_EQ(back.superseded, r.superseded);
  ASSERT_TRUE(back.X_MapCamera_corrected.has_value());
  EXPECT_EQ(back.X_MapCamera_corrected->orientation.coeffs(), corrected.orientation.coeffs());
  EXPECT_EQ(back.corrected_by_scene, 3);
}

// The journal's model-after reads back as written; stored text this release cannot read is kInternal naming the row
// (not a parser's exception, which the API would not map to a status).
TEST(SceneStoredDocumentsTest, ModelAfterRoundTripsAndUnreadableTextIsAnInternalErrorNamingTheRow) {
  engine::FrameCounts counts;
  counts.supported = 11;
  counts.reset = 12;
  counts.movable = 13;
  counts.dynamic = 14;
  counts.no_depth = 15;
  engine::SettleState settle;
  settle.movable_at_keyframe = 21;
  settle.reset_since_keyframe = 22;
  settle.previous_movable = 23;
  settle.stable_frames = 4;
  const scene_stored::ModelAfter back =
      scene_stored::DecodeModelAfter(scene_stored::EncodeModelAfter(counts, settle), 7, 9);
  EXPECT_EQ(back.counts.supported, 11u);
  EXPECT_EQ(back.counts.reset, 12u);
  EXPECT_EQ(back.counts.movable, 13u);
  EXPECT_EQ(back.counts.dynamic, 14u);
  EXPECT_EQ(back.counts.no_depth, 15u);
  EXPECT_EQ(back.settle.movable_at_keyframe, 21);
  EXPECT_EQ(back.settle.reset_since_keyframe, 22);
  EXPECT_EQ(back.settle.previous_movable, 23);
  EXPECT_EQ(back.settle.stable_frames, 4);
  const auto message_of = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const Error& e) {
      return e.code() == ErrorCode::kInternal ? e.what() : "another code";
    }
    return "no error";
  };
  storage::JournalModelAfter negative = scene_stored::EncodeModelAfter(counts, settle);
  negative.movable_px = -1;
  EXPECT_NE(message_of([&] { scene_stored::DecodeModelAfter(negative, 7, 9); }).find("frame 9 of scene 7"), std::string::npos);
  storage::JournalModelAfter below = scene_stored::EncodeModelAfter(counts, settle);
  below.settle_previous_movable_px = -2;
  EXPECT_NE(message_of([&] { scene_stored::DecodeModelAfter(below, 7, 9); }).find("frame 9 of scene 7"), std::string::npos);
  storage::MergeReportRecord unknown_strategy;
  unknown_strategy.strategy = "sideways";
  EXPECT_NE(message_of([&] { scene_stored::DecodeMergeReport(unknown_strategy, 7); }).find("scene 7"), std::string::npos);
}

TEST_F(SceneServiceTest, AnUnreadableStoredMergeReportIsAnInternalErrorNotACrash) {
  const std::int64_t id = scenes_->Open("home", At({0, 0, 1})).id;
  scenes_->Close("home", id);
  store_->Write([&](storage::Connection& c) {
    // A merged model with a negative point count: no row this release writes.
    storage::Statement(c, "INSERT INTO scene_merge_models VALUES (?, 0, 3, 0, 0, NULL, NULL, 0, 0, 0, NULL, -5, 0, '', "
                          "0, 0, 0, 0, 0, 0, 0, NULL, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, '')")
        .Bind(1, id).Run();
    storage::Statement(c, "UPDATE scene_models SET merge_list_rows = 1 WHERE id = ?").Bind(1, id).Run();
    return 0;
  });
  SceneService fresh(*store_, SceneLimits{}, MergeSettings{}, clock_);
  try {
    fresh.Get("home", id);
    ADD_FAILURE() << "an unreadable merge report was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    EXPECT_NE(std::string(e.what()).find("merge report"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace anchordb::services
