// EventService with SceneService and the analysis queue on one Store, without HTTP: a keyframe analysis of one map
// in flight does not hold up writes and analyses of another map, and an analysis whose inputs another writer changed
// meanwhile is computed again.
#include "services/events/event_service.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "services/events/analysis_queue.h"
#include "services/scene/scene_service.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "tests/support/temp_dir.h"
#include "tests/support/wall_and_box.h"

namespace anchordb::services {
namespace event_service_test {


std::vector<std::uint16_t> Depth(bool box) { return testing::WallDepthMm(box); }

class EventServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    storage::StoreOptions so;
    so.path = dir_.File("events.sqlite");
    store_ = std::make_unique<storage::Store>(so);
    store_->Write([](storage::Connection& c) {
      storage::InsertMap(c, {"a", "A", 1});
      storage::InsertMap(c, {"b", "B", 1});
    });
    scenes_ = std::make_unique<SceneService>(*store_, SceneLimits{});
    events_ = std::make_unique<EventService>(*store_, nullptr, EventSettings{});
    AnalysisQueueSettings q;
    q.threads = 2;  // workers only where a test starts them; two, so that two maps' analyses can overlap
    queue_ = std::make_unique<AnalysisQueue>(*store_, *events_, q);
    scenes_->SetKeyframeListener(queue_.get());
  }
  void TearDown() override {
    queue_.reset();
    scenes_.reset();
    events_.reset();
    store_.reset();
  }
  // The scene calls of these tests (one place to adapt when the scene service's requests change).
  std::int64_t OpenScene(const std::string& map) {
    OpenSceneRequest r;
    r.camera = testing::WallCamera();
    r.stamp_ns = 1'000'000'000'000LL;
    return scenes_->Open(map, r).id;
  }
  FrameResult AddFrame(const std::string& map, std::int64_t scene, const std::vector<std::uint16_t>& depth, std::int64_t stamp_ns,
                       bool wait_for_analysis = false) {
    return scenes_->AddFrame(map, scene, testing::RawFrame(depth, stamp_ns, wait_for_analysis));
  }
  std::size_t Keyframes(const std::string& map, std::int64_t scene) {
    return store_->Read([&](storage::Connection& c) { return storage::ListKeyframes(c, map, scene).size(); });
  }

  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<SceneService> scenes_;
  std::unique_ptr<EventService> events_;
  std::unique_ptr<AnalysisQueue> queue_;
};

TEST_F(EventServiceTest, AnotherMapsFrameAndAnalysisCompleteWhileAKeyframeAnalysisIsInFlight) {
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> blocked_once{false};
  events_->SetAnalysisHookForTesting([&](const std::string& map) {
    if (map != "a" || blocked_once.exchange(true)) return;
    entered.set_value();
    released.wait();
  });
  queue_->Start();
  const std::int64_t a = OpenScene("a"), b = OpenScene("b");
  // Map a's first frame stores its begin keyframe and answers at once; its analysis (a worker) stops before its write.
  const FrameResult out_a = AddFrame("a", a, Depth(false), 1'000'000'000'100LL);
  ASSERT_TRUE(out_a.keyframe.has_value());
  ASSERT_TRUE(out_a.keyframe->analysis.has_value());
  EXPECT_EQ(out_a.keyframe->analysis->state, AnalysisState::kPending);
  ASSERT_EQ(entered.get_future().wait_for(std::chrono::seconds(30)), std::future_status::ready);
  // Meanwhile map b's first frame: its keyframe (a write) and, waited for, the keyframe's analysis (the other worker).
  std::future<FrameResult> frame_b = std::async(std::launch::async, [&] { return AddFrame("b", b, Depth(false), 1'000'000'000'100LL, true); });
  const bool b_done = frame_b.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
  release.set_value();  // before asserting, so that both threads finish
  ASSERT_TRUE(b_done) << "a write and analysis on map b waited for the analysis of map a";
  const FrameResult out_b = frame_b.get();
  ASSERT_TRUE(out_b.keyframe.has_value());
  EXPECT_EQ(out_b.keyframe->analysis->state, AnalysisState::kDone);
  EXPECT_EQ(Keyframes("b", b), 1u);
  EXPECT_EQ(queue_->Await(out_a.keyframe->id).state, AnalysisState::kDone);
}

TEST_F(EventServiceTest, AnAnalysisWhoseInstancesChangedMeanwhileIsComputedAgain) {
  CreateInstanceRequest cup;
  cup.kind = InstanceKind::kObject;
  cup.label = "cup";
  cup.position_m = {5.0, 5.0, 0.0};
  const std::int64_t cup_id = events_->CreateInstance("a", cup).id;
  int analyses = 0;
  events_->SetAnalysisHookForTesting([&](const std::string& map) {
    if (map != "a" || ++analyses != 2) return;
    events_->PinInstance("a", cup_id, true);  // another writer changes the map's instances before the write
  });
  const std::int64_t a = OpenScene("a");
  AddFrame("a", a, Depth(false), 1'000'000'000'100LL);  // begin keyframe: analysis 1 (queued)
  EXPECT_EQ(analyses, 0);
  EXPECT_EQ(queue_->Drain(), 1);
  EXPECT_EQ(analyses, 1);
  AddFrame("a", a, Depth(true), 1'000'000'000'200LL);
  // Closes action layer 0: analysis 2, changed, analysis 3 (the queue runs in this thread: no worker was started).
  const KeyframeResult keyframe = scenes_->Keyframe("a", a, true);
  EXPECT_EQ(analyses, 3);
  ASSERT_TRUE(keyframe.keyframe.analysis.has_value());
  ASSERT_EQ(keyframe.keyframe.analysis->state, AnalysisState::kDone);
  ASSERT_TRUE(keyframe.keyframe.analysis->result.has_value());
  const KeyframeAnalysis& analysis = *keyframe.keyframe.analysis->result;
  ASSERT_EQ(analysis.events.size(), 1u);
  EXPECT_EQ(analysis.events[0].type, "added");
  EXPECT_EQ(analysis.action_layer, 0);
  const EventPage page = events_->ListEvents("a", EventQuery{});
  ASSERT_EQ(page.events.size(), 1u);  // written once
  EXPECT_TRUE(events_->GetInstance("a", cup_id).pinned);
  EXPECT_EQ(events_->ListInstances("a", InstanceQuery{}).instances.size(), 2u);
}

TEST_F(EventServiceTest, AnotherMapsInstanceChangingMeanwhileDoesNotComputeAnAnalysisAgain) {
  CreateInstanceRequest cup;
  cup.kind = InstanceKind::kObject;
  cup.label = "cup";
  cup.position_m = {5.0, 5.0, 0.0};
  const std::int64_t other_cup = events_->CreateInstance("b", cup).id;
  int analyses = 0;
  events_->SetAnalysisHookForTesting([&](const std::string& map) {
    if (map != "a" || ++analyses != 2) return;
    events_->PinInstance("b", other_cup, true);  // a write to map b between map a's analysis and its write
  });
  const std::int64_t a = OpenScene("a");
  AddFrame("a", a, Depth(false), 1'000'000'000'100LL);
  EXPECT_EQ(queue_->Drain(), 1);
  AddFrame("a", a, Depth(true), 1'000'000'000'200LL);
  const KeyframeResult keyframe = scenes_->Keyframe("a", a, true);
  EXPECT_EQ(analyses, 2) << "map a's count did not change: its analysis is written as computed";
  ASSERT_TRUE(keyframe.keyframe.analysis.has_value());
  ASSERT_EQ(keyframe.keyframe.analysis->state, AnalysisState::kDone);
  ASSERT_TRUE(keyframe.keyframe.analysis->result.has_value());
  EXPECT_EQ(keyframe.keyframe.analysis->result->events.size(), 1u);
  EXPECT_TRUE(events_->GetInstance("b", other_cup).pinned);
}

}  // namespace
}  // namespace anchordb::services
