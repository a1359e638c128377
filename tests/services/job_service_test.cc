// The job service (api/job_service.h) around forgetting on a real SQLite file: validation before queueing, results,
// and jobs found running or queued at start-up marked interrupted.
// Suite names are lower case so that `ctest -R forget` selects them.
#include "services/jobs/job_service.h"

#include <gtest/gtest.h>

#include <memory>

#include "schema/error.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace {

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
};

TEST_F(forgetting_job, BadInputQueuesNothingAndAGoodJobSucceeds) {
  JobService jobs(*store_);
  EXPECT_THROW(jobs.SubmitForget("home", Json::parse(R"({"policy": {"keyframe_max_age_s": -1}})")), Error);
  EXPECT_THROW(jobs.SubmitForget("home", Json::parse(R"({"policy": {"nonsense": 1}})")), Error);
  try {
    jobs.SubmitForget("nowhere", Json::object());
    FAIL() << "no error for an unknown map";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
  EXPECT_EQ(Jobs(), 0);
  const Json submitted = jobs.SubmitForget("home", Json::parse(R"({"dry_run": true})"));
  EXPECT_EQ(submitted["status"], "queued");
  ASSERT_TRUE(jobs.WaitIdle(30));
  const Json job = jobs.Get(submitted["job"].get<std::int64_t>());
  EXPECT_EQ(job["status"], "succeeded") << job.dump();
  EXPECT_EQ(job["kind"], "forget");
  EXPECT_EQ(job["map"], "home");
  EXPECT_EQ(job["progress"], 1.0);
  EXPECT_EQ(job["request"]["dry_run"], true);
  EXPECT_EQ(job["result"]["dry_run"], true);
  EXPECT_EQ(job["result"]["features_deduplicated"], 0);
  EXPECT_TRUE(job["error"].is_null());
  const Json real = jobs.SubmitForget("home", Json::parse(R"({"policy": {"vacuum": true}})"));
  ASSERT_TRUE(jobs.WaitIdle(30));
  const Json done = jobs.Get(real["job"].get<std::int64_t>());
  EXPECT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(done["result"]["committed"], true);
  EXPECT_EQ(done["result"]["vacuum"]["mode"], "switched_to_incremental");
  try {
    jobs.Get(999);
    FAIL() << "no error for an unknown job";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
}

TEST_F(forgetting_job, JobsFoundRunningOrQueuedAtStartAreMarkedInterrupted) {
  store_->Write([](Connection& c) {
    c.Exec("INSERT INTO jobs (kind, map_id, status, stage, progress, created_ns, updated_ns) VALUES "
           "('forget', 'home', 'running', 'keyframes', 0.5, 1, 1), ('forget', 'home', 'queued', '', 0, 2, 2), "
           "('forget', 'home', 'succeeded', 'done', 1, 3, 3)");
  });
  JobService jobs(*store_);
  EXPECT_EQ(jobs.interrupted_at_start(), 2);
  const Json running = jobs.Get(1), queued = jobs.Get(2), done = jobs.Get(3);
  EXPECT_EQ(running["status"], "failed");
  EXPECT_EQ(running["error"], "interrupted by a server stop (stage keyframes)");
  EXPECT_EQ(queued["status"], "failed");
  EXPECT_EQ(queued["error"], "interrupted by a server stop");
  EXPECT_EQ(done["status"], "succeeded");
}

}  // namespace
}  // namespace anchordb::services
