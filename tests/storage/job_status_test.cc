// A job's status has one table of stored names: every status round-trips through it, an unknown name is a corrupt
// row (kInternal), and a job written with a status reads back with it on both engines.
#include "storage/job_status.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/job_repository.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace job_status_test {

TEST(JobStatusNames, EveryStatusRoundTripsAndAnUnknownNameIsCorrupt) {
  for (JobStatus s : {JobStatus::kQueued, JobStatus::kRunning, JobStatus::kSucceeded, JobStatus::kFailed}) {
    EXPECT_EQ(JobStatusFromName(JobStatusName(s)), s) << JobStatusName(s);
  }
  EXPECT_STREQ(JobStatusName(JobStatus::kSucceeded), "succeeded");
  try {
    JobStatusFromName("cancelled");
    ADD_FAILURE() << "an unknown status was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
  }
}

class JobStatusRepositoryTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, JobStatusRepositoryTest, testing::BothEngines(), testing::EngineName);

TEST_P(JobStatusRepositoryTest, AStatusWrittenReadsBack) {
  StoreOptions so;
  so.path = db_.location();
  Store store(so);
  const std::int64_t id = store.Write([](Connection& c) { return InsertJob(c, "forget", std::nullopt, "{}", 10, "0000000a"); });
  EXPECT_EQ(store.Read([&](Connection& c) { return FindJob(c, id)->status; }), JobStatus::kQueued);
  const std::string result = "{}";
  store.Write([&](Connection& c) { SetJobStatus(c, id, JobStatus::kSucceeded, "done", 1.0, &result, nullptr, 20); });
  const std::optional<JobRecord> done = store.Read([&](Connection& c) { return FindJob(c, id); });
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->status, JobStatus::kSucceeded);
  EXPECT_EQ(done->stage, "done");
}

}  // namespace
}  // namespace anchordb::storage
