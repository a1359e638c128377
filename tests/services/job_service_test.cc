// The job service (services/jobs/job_service.h) on a real SQLite file: forgetting jobs validated before queueing,
// their results, jobs found running or queued at start-up marked interrupted, and the job registry: an unknown kind
// is refused, a kind registered by the test runs with progress, and is cancelled.
// Suite names are lower case so that `ctest -R forget` selects them.
#include "services/jobs/job_service.h"

#include <gtest/gtest.h>


#include <atomic>
#include <memory>
#include <thread>

#include "schema/error.h"
#include "storage/job_documents.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"
#include "tests/support/error_of.h"

namespace anchordb::services {
namespace job_service_test {

using testing::CodeOf;

using storage::Connection;
using storage::Statement;

class forgetting_job : public ::testing::Test {
 protected:
  void SetUp() override {
    storage::StoreOptions o;
    o.path = dir_.File("db.sqlite");
    o.reader_connections = 1;
    store_ = std::make_unique<storage::Store>(o);
    store_->Write([](Connection& c) { storage::InsertMap(c, {"home", "test", 1}); });
  }
  std::int64_t Jobs() {
    return store_->Read([](Connection& c) {
      Statement s(c, "SELECT count(*) FROM jobs");
      s.Step();
      return s.Int(0);
    });
  }
  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
  FakeClock clock_{1'700'000'000'000'000'000};
};

TEST_F(forgetting_job, BadInputQueuesNothingAndAGoodJobSucceeds) {
  JobService jobs(*store_, {}, clock_);
  storage::ForgetRequest negative;
  negative.policy.keyframe_max_age_s = -1;
  EXPECT_EQ(CodeOf([&] { jobs.SubmitForget("home", negative); }), ErrorCode::kUnprocessable);
  storage::ForgetRequest future;
  future.now_ns = clock_.NowNs() + 1;
  EXPECT_EQ(CodeOf([&] { jobs.SubmitForget("home", future); }), ErrorCode::kUnprocessable);
  EXPECT_EQ(CodeOf([&] { jobs.SubmitForget("nowhere", {}); }), ErrorCode::kNotFound);
  EXPECT_EQ(CodeOf([&] { jobs.SubmitBackup({}); }), ErrorCode::kUnprocessable);  // no backup_dir
  EXPECT_EQ(CodeOf([&] { jobs.SubmitBackup({"../x"}); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(Jobs(), 0);
  storage::ForgetRequest dry;
  dry.dry_run = true;
  const JobTicket submitted = jobs.SubmitForget("home", dry);
  EXPECT_EQ(submitted.kind, "forget");
  EXPECT_EQ(submitted.map, "home");
  ASSERT_TRUE(jobs.WaitIdle(30));
  const JobView job = jobs.Get(submitted.job);
  EXPECT_EQ(job.status, JobStatus::kSucceeded) << job.error.value_or("");
  EXPECT_EQ(job.kind, "forget");
  EXPECT_EQ(job.map, "home");
  EXPECT_EQ(job.progress, 1.0);
  EXPECT_EQ(job.created_ns, clock_.NowNs());
  const storage::ForgetRequest request = storage::DecodeForgetRequest(job.request.encoded, "job");
  EXPECT_TRUE(request.dry_run);
  EXPECT_EQ(request.policy.keyframe_max_age_s, 7 * 86400.0);
  ASSERT_TRUE(job.result);
  const storage::ForgetReport result = storage::DecodeForgetReport(job.result->encoded, "job");
  EXPECT_TRUE(result.dry_run);
  EXPECT_EQ(result.now_ns, clock_.NowNs());  // aged from the service's clock
  EXPECT_EQ(result.features_deduplicated, 0);
  EXPECT_FALSE(job.error);
  storage::ForgetRequest vacuum;
  vacuum.policy.vacuum = true;
  const JobTicket real = jobs.SubmitForget("home", vacuum);
  ASSERT_TRUE(jobs.WaitIdle(30));
  const JobView done = jobs.Get(real.job);
  EXPECT_EQ(done.status, JobStatus::kSucceeded) << done.error.value_or("");
  ASSERT_TRUE(done.result);
  const storage::ForgetReport report = storage::DecodeForgetReport(done.result->encoded, "job");
  EXPECT_TRUE(report.committed);
  EXPECT_EQ(report.vacuum_mode, "switched_to_incremental");
  EXPECT_EQ(CodeOf([&] { jobs.Get(999); }), ErrorCode::kNotFound);
  EXPECT_FALSE(jobs.Cancel(real.job));  // finished already
}

TEST_F(forgetting_job, JobsFoundRunningOrQueuedAtStartAreMarkedInterrupted) {
  store_->Write([](Connection& c) {
    c.Exec("INSERT INTO jobs (kind, map_id, status, stage, progress, created_ns, updated_ns) VALUES "
           "('forget', 'home', 'running', 'keyframes', 0.5, 1, 1), ('forget', 'home', 'queued', '', 0, 2, 2), "
           "('forget', 'home', 'succeeded', 'done', 1, 3, 3)");
    // Killed in the vacuum after its deletions committed (the result is recorded with them), by a version before
    // migration 0024 (its result is JSON text).
    c.Exec("INSERT INTO jobs (kind, map_id, status, stage, progress, result, created_ns, updated_ns) VALUES "
           "('forget', 'home', 'running', 'vacuum', 0.9, '{\"committed\":true}', 4, 4)");
  });
  JobService jobs(*store_, {}, clock_);
  EXPECT_EQ(jobs.interrupted_at_start(), 3);
  EXPECT_EQ(jobs.Get(4).status, JobStatus::kFailed);
  EXPECT_EQ(jobs.Get(4).error, "interrupted by a server stop (stage vacuum) (after the deletions were committed: see result)");
  ASSERT_TRUE(jobs.Get(4).result);
  EXPECT_EQ(jobs.Get(4).result->legacy_json, "{\"committed\":true}");
  EXPECT_TRUE(jobs.Get(4).result->encoded.empty());
  const JobView running = jobs.Get(1), queued = jobs.Get(2), done = jobs.Get(3);
  EXPECT_EQ(running.status, JobStatus::kFailed);
  EXPECT_EQ(running.error, "interrupted by a server stop (stage keyframes)");
  EXPECT_EQ(running.updated_ns, clock_.NowNs());
  EXPECT_EQ(queued.status, JobStatus::kFailed);
  EXPECT_EQ(queued.error, "interrupted by a server stop");
  EXPECT_EQ(done.status, JobStatus::kSucceeded);
}

// A kind of the test's own: counts up in steps until told to finish or cancelled.
struct Counter {
  std::atomic<int> steps{0};
  std::atomic<bool> finish{false};
  JobKind Kind() {
    JobKind kind;
    kind.name = "count";
    kind.first_stage = "counting";
    kind.check = [](const JobSubmission& s) {
      if (s.request != R"({"to":"end"})") throw Error(ErrorCode::kInvalidArgument, "count to the end", "to");
    };
    kind.run = [this](JobContext& job) -> std::optional<std::string> {
      for (int i = 0; !finish; ++i) {
        job.Progress("counting", 0.5);
        steps = i + 1;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      job.Progress("finishing", 0.9);
      return R"({"steps":)" + std::to_string(steps.load()) + "}";
    };
    return kind;
  }
};

bool WaitFor(const std::function<bool()>& done) {
  for (int i = 0; i < 10000 && !done(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return done();
}

TEST_F(forgetting_job, RegistryRefusesUnknownKindsAndRunsARegisteredOne) {
  JobService jobs(*store_, {}, clock_);
  EXPECT_EQ(CodeOf([&] { jobs.Submit("count", std::nullopt, R"({"to":"end"})"); }), ErrorCode::kInvalidArgument);
  Counter counter;
  jobs.Register(counter.Kind());
  EXPECT_EQ(CodeOf([&] { jobs.Register(counter.Kind()); }), ErrorCode::kConflict);
  EXPECT_EQ(CodeOf([&] { jobs.Submit("count", std::nullopt, R"({"to":"start"})"); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(CodeOf([&] { jobs.Submit("count", "home", R"({"to":"end"})"); }), ErrorCode::kInvalidArgument);  // no map
  EXPECT_EQ(Jobs(), 0);
  const JobTicket t = jobs.Submit("count", std::nullopt, R"({"to":"end"})");
  ASSERT_TRUE(WaitFor([&] { return counter.steps > 3; }));
  const JobView live = jobs.Get(t.job);
  EXPECT_EQ(live.status, JobStatus::kRunning);
  EXPECT_EQ(live.stage, "counting");
  EXPECT_EQ(live.progress, 0.5);
  counter.finish = true;
  ASSERT_TRUE(jobs.WaitIdle(30));
  const JobView done = jobs.Get(t.job);
  EXPECT_EQ(done.status, JobStatus::kSucceeded);
  EXPECT_EQ(done.stage, "done");
  EXPECT_EQ(done.progress, 1.0);
  ASSERT_TRUE(done.result);
  EXPECT_NE(done.result->encoded.find("steps"), std::string::npos);  // the kind's own bytes, stored as they came
}

TEST_F(forgetting_job, RegisteredKindIsCancelledRunningOrQueued) {
  JobService jobs(*store_, {}, clock_);
  Counter counter;
  jobs.Register(counter.Kind());
  const JobTicket running = jobs.Submit("count", std::nullopt, R"({"to":"end"})");
  const JobTicket queued = jobs.Submit("count", std::nullopt, R"({"to":"end"})");
  ASSERT_TRUE(WaitFor([&] { return counter.steps > 3; }));
  EXPECT_TRUE(jobs.Cancel(queued.job));
  EXPECT_TRUE(jobs.Cancel(running.job));
  ASSERT_TRUE(jobs.WaitIdle(30));
  const JobView a = jobs.Get(running.job), b = jobs.Get(queued.job);
  EXPECT_EQ(a.status, JobStatus::kFailed);
  EXPECT_EQ(a.error, "cancelled");
  EXPECT_EQ(a.stage, "counting");
  EXPECT_FALSE(a.result);
  EXPECT_EQ(b.status, JobStatus::kFailed);
  EXPECT_EQ(b.error, "cancelled");
  EXPECT_FALSE(counter.finish);
  EXPECT_EQ(CodeOf([&] { jobs.Cancel(999); }), ErrorCode::kNotFound);
}

TEST_F(forgetting_job, StoppingTheServiceInterruptsARunningJob) {
  Counter counter;
  std::int64_t id = 0;
  {
    JobService jobs(*store_, {}, clock_);
    jobs.Register(counter.Kind());
    id = jobs.Submit("count", std::nullopt, R"({"to":"end"})").job;
    ASSERT_TRUE(WaitFor([&] { return counter.steps > 3; }));
  }
  JobService again(*store_, {}, clock_);
  EXPECT_EQ(again.interrupted_at_start(), 0);  // the stop recorded the failure itself
  const JobView job = again.Get(id);
  EXPECT_EQ(job.status, JobStatus::kFailed);
  EXPECT_EQ(job.error, "interrupted by a server stop");
}

}  // namespace
}  // namespace anchordb::services
