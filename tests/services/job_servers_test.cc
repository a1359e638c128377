// Jobs with several servers on one database (issue 31; services/jobs/job_service.h): a server starting beside a
// running one leaves that server's running job alone, and marks interrupted the job of a server that is gone once
// it has seen it gone twice. On SQLite one server has the file: a second service marks the first's jobs at start.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <thread>

#include "services/jobs/job_service.h"
#include "storage/job_repository.h"
#include "storage/server_presence.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/test_store.h"

namespace anchordb::services {
namespace job_servers_test {

using namespace std::string_literals;

// Runs until told to finish.
struct Latch {
  std::atomic<bool> started{false}, finish{false};
  JobKind Kind() {
    JobKind kind;
    kind.name = "hold";
    kind.first_stage = "holding";
    kind.check = [](const JobSubmission&) {};
    kind.run = [this](JobContext& job) -> std::optional<std::string> {
      started = true;
      while (!finish) {
        job.Progress("holding", 0.5);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      return std::string("held");
    };
    return kind;
  }
};

// Lets the latch's job end when the test leaves, before the service that runs it joins its worker.
struct FinishOnExit {
  Latch& latch;
  ~FinishOnExit() { latch.finish = true; }
};

bool WaitFor(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  return done();
}

class JobServersTest : public ::testing::TestWithParam<storage::Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, JobServersTest, testing::BothEngines(), testing::EngineName);

TEST_P(JobServersTest, ARunningServersJobIsLeftAloneAndAGoneServersJobIsMarkedInterrupted) {
  // The latch outlives the services whose worker runs its job; the guard, destroyed first, lets that job end so
  // that a service's destructor can join its worker on every path out of the test.
  Latch latch;
  const auto store_a = testing::OpenStoreWithMaps(db_.location(), {"home"});
  const auto store_b = testing::OpenStoreWithMaps(db_.location(), {});
  JobSettings fast;
  fast.reap_interval_s = 0.05;
  JobService a(*store_a, fast);
  const FinishOnExit finish_on_exit{latch};
  a.Register(latch.Kind());
  const std::int64_t held = a.Submit("hold", std::nullopt, "{}").job;
  ASSERT_TRUE(WaitFor([&] { return latch.started.load(); }, 30));

  // A server that is gone without a word (a kill -9): its presence ended, its job left running.
  auto gone = std::make_unique<storage::ServerPresence>(db_.location(), storage::ConnectionOptions{}, 99);
  const std::int64_t orphan = store_a->Write([&](storage::Connection& c) {
    const std::int64_t id = storage::InsertJob(c, "forget", "home"s, "", 1, gone->id());
    storage::SetJobStatus(c, id, JobStatus::kRunning, "keyframes", 0.3, nullptr, nullptr, 2);
    return id;
  });

  JobService b(*store_b, fast);
  EXPECT_NE(b.server_id(), a.server_id());
  if (GetParam() == storage::Engine::kSqlite) {
    // One server per file: whatever another service left unfinished is a stopped server's.
    EXPECT_EQ(b.interrupted_at_start(), 2);
    EXPECT_EQ(b.Get(orphan).status, JobStatus::kFailed);
    return;
  }
  EXPECT_EQ(b.interrupted_at_start(), 0) << "both servers are running";
  // Several passes of b's worker while both run: nothing is marked.
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  EXPECT_EQ(b.interrupted_since_start(), 0);
  EXPECT_EQ(b.Get(held).status, JobStatus::kRunning);
  EXPECT_EQ(b.Get(orphan).status, JobStatus::kRunning);

  gone.reset();
  ASSERT_TRUE(WaitFor([&] { return b.Get(orphan).status == JobStatus::kFailed; }, 30));
  EXPECT_EQ(b.Get(orphan).error, "interrupted by a server stop (stage keyframes)");
  EXPECT_EQ(b.interrupted_since_start(), 1);
  EXPECT_EQ(b.Get(held).status, JobStatus::kRunning) << "the running server's job is still its own";

  latch.finish = true;
  ASSERT_TRUE(a.WaitIdle(30));
  EXPECT_EQ(a.Get(held).status, JobStatus::kSucceeded);
}

}  // namespace
}  // namespace anchordb::services
