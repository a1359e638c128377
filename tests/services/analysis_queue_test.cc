// The keyframe analysis queue (services/events/analysis_queue.h) with the scene and event services on one real
// SQLite file, without HTTP: answers do not wait, the explicit wait and the drain give the events, one map's keyframes
// are analysed in keyframe order, failures are retried and reported, rows survive a restart, a deleted keyframe is
// skipped, and a model's reads do not wait for its analysis. No test depends on timing: workers are started only where
// a test needs concurrency, and the tests wait through Await / Drain or explicit hooks.
#include "services/events/analysis_queue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <functional>
#include <stdexcept>
#include <thread>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "services/scene/scene_service.h"
#include "storage/fault_vfs.h"
#include "storage/repositories.h"
#include "tests/support/temp_dir.h"
#include "tests/support/wall_and_box.h"

namespace anchordb::services {
namespace analysis_queue_test {

constexpr std::int64_t kT0 = 1'000'000'000'000LL;

std::vector<std::uint16_t> Depth(bool box) { return testing::WallDepthMm(box); }

// The calling thread's own niceness (Linux: a thread's tid as the "process").
int ThreadNice() { return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid))); }

class AnalysisQueueTest : public ::testing::Test {
 protected:
  void SetUp() override { Open(); }
  void TearDown() override { Close(); }
  void Open(AnalysisQueueSettings q = {}, bool fault_vfs = false) {
    storage::StoreOptions so;
    so.path = dir_.File("queue.sqlite");
    if (fault_vfs) so.connection.vfs = storage::fault::RegisterFaultVfs(false);
    store_ = std::make_unique<storage::Store>(so);
    store_->Write([](storage::Connection& c) {
      if (!storage::FindMap(c, "a")) storage::InsertMap(c, {"a", "A", 1});
      if (!storage::FindMap(c, "b")) storage::InsertMap(c, {"b", "B", 1});
    });
    scenes_ = std::make_unique<SceneService>(*store_, SceneLimits{});
    events_ = std::make_unique<EventService>(*store_, nullptr, EventSettings{});
    queue_ = std::make_unique<AnalysisQueue>(*store_, *events_, q, clock_);
    scenes_->SetKeyframeListener(queue_.get());
  }
  void Close() {
    queue_.reset();
    scenes_.reset();
    events_.reset();
    store_.reset();
  }
  // One nice worker 10 below `request_nice` and its catch-up worker from `catch_up_at` pending on; no refusal.
  void ReopenWithCatchUpAt(int catch_up_at, int request_nice) {
    Close();
    AnalysisQueueSettings q;
    q.threads = 1;
    q.nice = std::min(19, request_nice + 10);
    q.backlog = {catch_up_at, 0};
    Open(q);
  }
  std::int64_t OpenScene(const std::string& map) {
    OpenSceneRequest r;
    r.camera = testing::WallCamera();
    r.stamp_ns = kT0;
    return scenes_->Open(map, r).id;
  }
  FrameResult AddFrame(const std::string& map, std::int64_t scene, const std::vector<std::uint16_t>& depth, std::int64_t stamp_ns) {
    return scenes_->AddFrame(map, scene, testing::RawFrame(depth, stamp_ns));
  }
  // A model that saw a box appear: begin keyframe (empty wall), then a manual keyframe with the box. Returns the
  // manual keyframe's id; its analysis finds one "added" event.
  std::int64_t BoxAppears(const std::string& map, std::int64_t scene, std::int64_t t_ns) {
    AddFrame(map, scene, Depth(false), t_ns);
    AddFrame(map, scene, Depth(true), t_ns + 100);
    return scenes_->Keyframe(map, scene).keyframe.id;
  }
  std::size_t Events(const std::string& map) { return events_->ListEvents(map, EventQuery{}).events.size(); }

  testing::TempDir dir_;
  FakeClock clock_{kT0};
  std::unique_ptr<storage::Store> store_;
  std::unique_ptr<SceneService> scenes_;
  std::unique_ptr<EventService> events_;
  std::unique_ptr<AnalysisQueue> queue_;
};

TEST_F(AnalysisQueueTest, AKeyframeAnswersPendingAndItsEventsAppearAfterTheWait) {
  const std::int64_t s = OpenScene("a");
  const FrameResult first = AddFrame("a", s, Depth(false), kT0 + 100);
  ASSERT_TRUE(first.keyframe && first.keyframe->analysis);
  EXPECT_EQ(first.keyframe->analysis->state, AnalysisState::kPending);
  EXPECT_EQ(first.keyframe->analysis->keyframe_id, first.keyframe->id);
  AddFrame("a", s, Depth(true), kT0 + 200);
  const KeyframeResult manual = scenes_->Keyframe("a", s);
  ASSERT_TRUE(manual.keyframe.analysis);
  EXPECT_EQ(manual.keyframe.analysis->state, AnalysisState::kPending);
  EXPECT_FALSE(manual.keyframe.analysis->result);
  EXPECT_EQ(Events("a"), 0u);  // nothing analysed yet: no worker runs and nobody waited
  const AnalysisQueueView queued = queue_->View("a");
  EXPECT_EQ(queued.pending, 2);
  EXPECT_EQ(queued.oldest_pending_age_s, 0.0);  // the fake clock stands still
  const KeyframeAnalysisStatus done = queue_->Await(manual.keyframe.id);
  ASSERT_EQ(done.state, AnalysisState::kDone);
  ASSERT_TRUE(done.result);
  ASSERT_EQ(done.result->events.size(), 1u);
  EXPECT_EQ(done.result->events[0].type, "added");
  EXPECT_EQ(done.result->action_layer, 0);
  EXPECT_EQ(Events("a"), 1u);
  EXPECT_EQ(queue_->View("a").pending, 0);
  EXPECT_EQ(queue_->counters().done, 2);
  // Waiting again answers the same outcome; the request flag does the same in one call.
  EXPECT_EQ(queue_->Await(manual.keyframe.id).result->events.size(), 1u);
  AddFrame("a", s, Depth(false), kT0 + 300);
  const KeyframeResult removed = scenes_->Keyframe("a", s, true);
  ASSERT_EQ(removed.keyframe.analysis->state, AnalysisState::kDone);
  ASSERT_EQ(removed.keyframe.analysis->result->events.size(), 1u);
  EXPECT_EQ(removed.keyframe.analysis->result->events[0].type, "removed");
}

TEST_F(AnalysisQueueTest, OneMapsKeyframesAreAnalysedInKeyframeOrderAcrossItsModels) {
  Close();
  AnalysisQueueSettings q;
  q.threads = 3;
  Open(q);
  std::mutex m;
  std::vector<std::int64_t> order;
  int running = 0, most_running = 0;
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis& row) {
    std::lock_guard<std::mutex> lock(m);
    if (row.map_id == "a") order.push_back(row.keyframe_id);
  });
  events_->SetAnalysisHookForTesting([&](const std::string& map) {
    std::lock_guard<std::mutex> lock(m);
    if (map == "a") most_running = std::max(most_running, ++running), --running;
  });
  // Two models of map a, their keyframes interleaved, stored before any worker runs.
  const std::int64_t s1 = OpenScene("a"), s2 = OpenScene("a");
  std::vector<std::int64_t> stored;
  for (int round = 0; round < 3; ++round) {
    for (std::int64_t s : {s1, s2}) {
      const FrameResult f = AddFrame("a", s, Depth(round % 2 == 1), kT0 + 1000 * round + s);
      if (f.keyframe) stored.push_back(f.keyframe->id);
      stored.push_back(scenes_->Keyframe("a", s).keyframe.id);
    }
  }
  ASSERT_EQ(stored.size(), 8u);  // per model: begin, then a manual keyframe each round
  queue_->Start();
  EXPECT_EQ(queue_->Await(stored.back()).state, AnalysisState::kDone);
  EXPECT_EQ(queue_->Drain(), 0);  // the workers did them all
  EXPECT_EQ(order, stored);  // keyframe order, each once
  EXPECT_EQ(most_running, 1);
  // In that order, the second model's box is the first model's instance (no second "added"), seen removed by each.
  std::vector<std::pair<std::string, std::int64_t>> events;
  for (const EventView& e : events_->ListEvents("a", EventQuery{}).events) events.emplace_back(e.type, e.scene_id.value_or(-1));
  const std::vector<std::pair<std::string, std::int64_t>> expected = {{"added", s1}, {"removed", s1}, {"removed", s2}};
  EXPECT_EQ(events, expected);
}

TEST_F(AnalysisQueueTest, AFailingAnalysisIsRetriedAfterItsBackoffAndReported) {
  Close();
  AnalysisQueueSettings q;
  q.threads = 0;
  q.retry_initial_s = 2.0;
  q.max_attempts = 2;
  Open(q, true);
  const std::int64_t s = OpenScene("a");
  AddFrame("a", s, Depth(false), kT0 + 100);
  ASSERT_EQ(queue_->Drain(), 1);  // the begin keyframe
  AddFrame("a", s, Depth(true), kT0 + 200);
  scenes_->Keyframe("a", s);
  // The disk fails every write: the analysis' write (and the record of its failure) fail, transiently.
  storage::fault::Arm({storage::fault::FaultKind::kWrite, 1, 0});
  EXPECT_EQ(queue_->Drain(), 1);
  storage::fault::Disarm();
  ASSERT_TRUE(storage::fault::Fired());
  EXPECT_EQ(queue_->counters().failed_attempts, 1);
  EXPECT_EQ(Events("a"), 0u);  // nothing half-written
  EXPECT_EQ(queue_->View("a").pending, 1);
  EXPECT_EQ(queue_->Drain(), 0);  // its backoff (2 s on the fake clock) has not passed
  clock_.AdvanceNs(2'000'000'000LL);
  EXPECT_EQ(queue_->Drain(), 1);
  EXPECT_EQ(Events("a"), 1u);
  EXPECT_EQ(queue_->View("a").pending, 0);

  // A non-transient failure is written to its row (visible in View), retried, and given up after max_attempts; the
  // map's later keyframes are analysed after it.
  AddFrame("a", s, Depth(false), kT0 + 500);
  const std::int64_t failing = scenes_->Keyframe("a", s).keyframe.id;
  AddFrame("a", s, Depth(true), kT0 + 600);
  const std::int64_t later = scenes_->Keyframe("a", s).keyframe.id;
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis& row) {
    if (row.keyframe_id == failing) throw std::runtime_error("the analysis broke");
  });
  EXPECT_EQ(queue_->Drain(), 1);  // the failing one; the later one waits behind it
  AnalysisQueueView v = queue_->View("a");
  EXPECT_EQ(v.pending, 2);
  EXPECT_EQ(v.retrying, 1);
  ASSERT_EQ(v.failures.size(), 1u);
  EXPECT_EQ(v.failures[0].keyframe_id, failing);
  EXPECT_EQ(v.failures[0].attempts, 1);
  EXPECT_EQ(v.failures[0].last_error, "the analysis broke");
  EXPECT_FALSE(v.failures[0].failed);
  EXPECT_EQ(queue_->Drain(true), 2);  // attempt 2 gives up; then the later keyframe runs
  v = queue_->View("a");
  EXPECT_EQ(v.pending, 0);
  EXPECT_EQ(v.failed, 1);
  ASSERT_EQ(v.failures.size(), 1u);
  EXPECT_TRUE(v.failures[0].failed);
  EXPECT_EQ(queue_->Await(failing).state, AnalysisState::kFailed);
  EXPECT_EQ(queue_->Await(later).state, AnalysisState::kDone);
  EXPECT_EQ(queue_->counters().given_up, 1);
}

TEST_F(AnalysisQueueTest, QueuedAnalysesSurviveAStopAndRunWithTheNextQueue) {
  const std::int64_t s = OpenScene("a");
  const std::int64_t k = BoxAppears("a", s, kT0 + 100);
  Close();  // stopped with two analyses queued
  Open();
  EXPECT_EQ(queue_->View("a").pending, 2);
  EXPECT_EQ(Events("a"), 0u);
  EXPECT_EQ(queue_->Drain(), 2);
  EXPECT_EQ(Events("a"), 1u);
  // Its outcome is not in this process' memory: done, without the events inline.
  const KeyframeAnalysisStatus st = queue_->Await(k);
  EXPECT_EQ(st.state, AnalysisState::kDone);
}

TEST_F(AnalysisQueueTest, AKeyframeDeletedBeforeItsAnalysisIsSkipped) {
  const std::int64_t sa = OpenScene("a"), sb = OpenScene("b");
  const std::int64_t kb = BoxAppears("b", sb, kT0 + 100);
  const std::int64_t ka = BoxAppears("a", sa, kT0 + 100);
  // Map b goes (its keyframes and queue rows with it) after its analysis was taken from the queue.
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis& row) {
    if (row.map_id == "b") store_->Write([](storage::Connection& c) { storage::DeleteMap(c, "b"); });
  });
  EXPECT_EQ(queue_->Drain(), 3);  // b's first row (skipped, the map gone), then a's two
  EXPECT_EQ(queue_->Await(kb).state, AnalysisState::kDone);  // no row, no outcome: gone
  EXPECT_EQ(queue_->Await(ka).state, AnalysisState::kDone);
  EXPECT_EQ(queue_->counters().skipped, 1);
  EXPECT_EQ(Events("a"), 1u);
  EXPECT_EQ(queue_->View(std::nullopt).pending, 0);
}

TEST_F(AnalysisQueueTest, AModelsReadsAndFramesDoNotWaitForItsRunningAnalysis) {
  Close();
  AnalysisQueueSettings q;
  q.threads = 1;
  Open(q);
  const std::int64_t s = OpenScene("a");
  AddFrame("a", s, Depth(false), kT0 + 100);
  AddFrame("a", s, Depth(true), kT0 + 200);
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> once{false};
  events_->SetAnalysisHookForTesting([&](const std::string&) {  // the manual keyframe's analysis, mid-way
    if (!once.exchange(true)) return;  // the begin keyframe's
    entered.set_value();
    released.wait();
  });
  queue_->Start();
  const std::int64_t k = scenes_->Keyframe("a", s).keyframe.id;
  ASSERT_EQ(entered.get_future().wait_for(std::chrono::seconds(60)), std::future_status::ready);
  // The analysis of this model's keyframe is running (held in its hook): the model answers its reads and a frame.
  std::future<std::int64_t> reads = std::async(std::launch::async, [&] {
    EXPECT_EQ(scenes_->Get("a", s).id, s);
    scenes_->LayerSummary("a", s, SceneLayerKind::kMovable, false);
    scenes_->KeyframeImage("a", k, KeyframeImageKind::kDepth);
    events_->ListEvents("a", EventQuery{});
    return AddFrame("a", s, Depth(true), kT0 + 300).frames;
  });
  const bool answered = reads.wait_for(std::chrono::seconds(60)) == std::future_status::ready;  // a hang's bound, not a timing
  EXPECT_EQ(queue_->View("a").running, 1);  // still held: the reads were answered during the analysis
  release.set_value();
  ASSERT_TRUE(answered) << "a read of the model waited for its keyframe analysis";
  EXPECT_EQ(reads.get(), 3);
  EXPECT_EQ(queue_->Await(k).state, AnalysisState::kDone);
}

TEST_F(AnalysisQueueTest, TheAnalysisReadsTheKeyframesImagesAsTheModelHadThem) {
  const std::int64_t s = OpenScene("a");
  AddFrame("a", s, Depth(false), kT0 + 100);
  AddFrame("a", s, Depth(true), kT0 + 200);
  const ExportedLayer background = scenes_->Layer("a", s, SceneLayerKind::kStatic, SceneLayerEncoding::kRaw, false);
  const std::int64_t k = scenes_->Keyframe("a", s).keyframe.id;
  const auto notice = store_->Read([&](storage::Connection& c) { return LoadKeyframeNotice(c, "a", k); });
  ASSERT_TRUE(notice);
  EXPECT_EQ(notice->kind, "manual");
  EXPECT_EQ(notice->stamp_ns, kT0 + 200);
  EXPECT_EQ(notice->action_layer, 1);
  EXPECT_EQ(notice->depth_mm, Depth(true));  // the latest frame (raw, 1000 units per metre) as the model kept it
  std::vector<float> metres(testing::kWallW * testing::kWallH);
  ASSERT_EQ(background.body.size(), metres.size() * 4);
  std::memcpy(metres.data(), background.body.data(), background.body.size());
  std::vector<std::uint16_t> mm(metres.size());
  for (std::size_t i = 0; i < mm.size(); ++i) mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(metres[i] * 1000.0f), 0L, 65535L));
  EXPECT_EQ(notice->background_mm, mm);
  EXPECT_FALSE(store_->Read([&](storage::Connection& c) { return LoadKeyframeNotice(c, "a", k + 100); }));
}


// Declared after the locals a run hook reads: when the test leaves, on any path, it first releases what the hook
// waits for, then stops the queue's workers, before those locals are destroyed.
struct StopOnExit {
  std::function<void()> release;
  AnalysisQueue& queue;
  ~StopOnExit() {
    if (release) release();
    queue.Stop();
  }
};

void SetValueOnce(std::promise<void>& p) {
  try {
    p.set_value();
  } catch (const std::future_error&) {  // already set by the test
  }
}

// Back-pressure (engine/events/analysis_backlog.h): with max_pending analyses of a map pending, its frames and manual
// keyframes are refused with kUnavailable and store nothing; another map and a close are not refused; once the
// analyses catch up the map takes frames again.
TEST_F(AnalysisQueueTest, AMapFarBehindRefusesFramesUntilItsAnalysesCatchUp) {
  Close();
  AnalysisQueueSettings q;
  q.threads = 1;
  q.backlog = {0, 3};  // no catch-up workers: one worker, held below
  Open(q);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis&) { released.wait(); });
  const StopOnExit stop{[&] { SetValueOnce(release); }, *queue_};
  const std::int64_t s = OpenScene("a"), s2 = OpenScene("a");
  queue_->Start();
  AddFrame("a", s, Depth(false), kT0 + 100);  // the begin keyframe: pending 1 (taken, held)
  AddFrame("a", s2, Depth(false), kT0 + 100);  // the second model's begin keyframe: pending 2
  AddFrame("a", s, Depth(true), kT0 + 200);
  scenes_->Keyframe("a", s);  // pending 3: at the bound
  const SceneInfo before = scenes_->Get("a", s);
  ASSERT_TRUE(before.state);
  const std::int64_t frames = before.state->frames;
  const auto refused = [](const std::function<void()>& call) {
    try {
      call();
    } catch (const Error& e) {
      return e.code() == ErrorCode::kOverloaded && std::string(e.what()).find("analysis_max_pending") != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(refused([&] { AddFrame("a", s, Depth(true), kT0 + 300); }));
  EXPECT_TRUE(refused([&] { scenes_->Keyframe("a", s); }));
  const SceneInfo after = scenes_->Get("a", s);
  EXPECT_EQ(after.state->frames, frames) << "a refused frame changed the model";
  EXPECT_EQ(after.keyframes.size(), before.keyframes.size()) << "a refused keyframe was stored";
  EXPECT_EQ(queue_->View("a").pending, 3) << "a refused keyframe was stored";
  EXPECT_EQ(queue_->counters().frames_refused, 2);
  const std::int64_t other = OpenScene("b");
  EXPECT_EQ(AddFrame("b", other, Depth(false), kT0 + 100).frames, 1) << "another map's frames are not held back";
  const CloseResult closed = scenes_->Close("a", s2);  // a close is never refused: its end keyframe makes 4
  ASSERT_TRUE(closed.keyframe);
  EXPECT_EQ(queue_->View("a").pending, 4);

  release.set_value();
  EXPECT_EQ(queue_->Await(closed.keyframe->id).state, AnalysisState::kDone);
  EXPECT_EQ(queue_->View("a").pending, 0);
  EXPECT_EQ(AddFrame("a", s, Depth(true), kT0 + 400).frames, frames + 1) << "caught up: frames are taken again";
  EXPECT_EQ(queue_->counters().frames_refused, 2);
}

// From catch_up_at pending analyses on, a map's analyses run at the requests' priority (the catch-up workers keep
// the niceness of the thread that started them); below it, at `nice`.
TEST_F(AnalysisQueueTest, AMapBehindIsAnalysedAtTheRequestsPriority) {
  const int request_nice = ThreadNice();
  ReopenWithCatchUpAt(2, request_nice);
  std::mutex m;
  std::vector<int> nice_of_run;
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis&) {
    std::lock_guard<std::mutex> lock(m);
    nice_of_run.push_back(ThreadNice());
  });
  const StopOnExit stop{nullptr, *queue_};
  const std::int64_t s = OpenScene("a");
  AddFrame("a", s, Depth(false), kT0 + 100);
  AddFrame("a", s, Depth(true), kT0 + 200);
  scenes_->Keyframe("a", s);
  const std::int64_t last = scenes_->Keyframe("a", s).keyframe.id;  // 3 pending before any worker runs
  queue_->Start();
  EXPECT_EQ(queue_->Await(last).state, AnalysisState::kDone);
  std::lock_guard<std::mutex> lock(m);
  ASSERT_EQ(nice_of_run.size(), 3u);
  EXPECT_EQ(nice_of_run[0], request_nice) << "3 pending: caught up";
  EXPECT_EQ(nice_of_run[1], request_nice) << "2 pending: caught up";
  EXPECT_GT(nice_of_run[2], request_nice) << "1 pending: in the background";
  EXPECT_EQ(queue_->counters().caught_up, 2);
}

// Whether this process may lower a thread's niceness (root, CAP_SYS_NICE or RLIMIT_NICE): a thread niced to 10 and
// set back.
bool MayLowerNiceness() {
  bool may = false;
  std::thread([&] {
    const auto tid = static_cast<id_t>(syscall(SYS_gettid));
    const int before = ThreadNice();
    may = setpriority(PRIO_PROCESS, tid, before + 10) == 0 && setpriority(PRIO_PROCESS, tid, before) == 0;
  }).join();
  return may;
}

// A nice worker's analysis that is running when its map falls catch_up_at behind is raised to the requests' priority
// where the process may lower a niceness; elsewhere it ends at its own.
TEST_F(AnalysisQueueTest, TheRunningAnalysisOfAMapFallingBehindIsRaisedWherePermitted) {
  const int request_nice = ThreadNice();
  ReopenWithCatchUpAt(2, request_nice);
  std::promise<void> entered, release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> first{true};
  std::atomic<int> first_nice_at_start{-100}, first_nice_at_end{-100};
  queue_->SetRunHookForTesting([&](const storage::QueuedAnalysis&) {
    if (!first.exchange(false)) return;
    first_nice_at_start = ThreadNice();
    entered.set_value();
    released.wait();
    first_nice_at_end = ThreadNice();
  });
  const StopOnExit stop{[&] { SetValueOnce(release); }, *queue_};
  const std::int64_t s = OpenScene("a");
  queue_->Start();
  AddFrame("a", s, Depth(false), kT0 + 100);  // pending 1: taken by the nice worker, held
  ASSERT_EQ(entered.get_future().wait_for(std::chrono::seconds(60)), std::future_status::ready);
  AddFrame("a", s, Depth(true), kT0 + 200);
  const std::int64_t last = scenes_->Keyframe("a", s).keyframe.id;  // pending 2: behind
  release.set_value();
  EXPECT_EQ(queue_->Await(last).state, AnalysisState::kDone);
  EXPECT_GT(first_nice_at_start.load(), request_nice);
  if (MayLowerNiceness()) {
    EXPECT_EQ(first_nice_at_end.load(), request_nice) << "raised while it ran";
    EXPECT_EQ(queue_->counters().raised, 1);
  } else {
    EXPECT_EQ(first_nice_at_end.load(), first_nice_at_start.load()) << "not permitted: it ends at its priority";
    EXPECT_EQ(queue_->counters().raised, 0);
  }
}

}  // namespace
}  // namespace anchordb::services
