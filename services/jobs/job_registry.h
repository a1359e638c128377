#pragma once
// The kinds of long work (SPEC §3 "Jobs"). A capability adds its kind by registering a JobKind (name, first stage,
// request check, runner) with JobService from its own file; JobService queues, runs one at a time, persists,
// reports progress and cancels jobs without knowing any kind. Built in: "forget" (services/jobs/forget_job.cc) and
// "backup" (services/jobs/backup_job.cc).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "services/jobs/job_types.h"
#include "storage/connection.h"

namespace anchordb::services {

// What a runner sees of its job.
class JobContext {
 public:
  virtual ~JobContext() = default;
  virtual std::int64_t id() const = 0;
  virtual const std::optional<std::string>& map() const = 0;
  // The request as stored at submission: the kind's own document, encoded (storage/document_codec.h).
  virtual const std::string& request() const = 0;
  // The service's clock [ns since the epoch].
  virtual std::int64_t NowNs() const = 0;
  // Publishes the live stage and the fraction done in [0, 1]. Throws Error(kOverloaded) once the job is cancelled
  // (Cancel, or a server stop): the runner unwinds (its transaction rolls back) and the job fails.
  virtual void Progress(std::string_view stage, double fraction) = 0;
  virtual void Progress(double fraction) = 0;  // in the current stage
  virtual bool Cancelled() const = 0;
  // While set, a cancellation also interrupts the statement running on `c` (Connection::Interrupt); nullptr clears it.
  virtual void SetInterruptible(storage::Connection* c) = 0;
  // Records the job's status inside the runner's own transaction on `c`, so that an outcome commits with the work
  // it describes (result_document, encoded: null keeps the stored result).
  virtual void Record(storage::Connection& c, JobStatus status, const std::string& stage, double progress,
                      const std::string* result_document) = 0;
};

// Makes `c` interruptible by a cancellation for the life of this object.
class InterruptibleScope {
 public:
  InterruptibleScope(JobContext& job, storage::Connection& c) : job_(job) { job_.SetInterruptible(&c); }
  ~InterruptibleScope() { job_.SetInterruptible(nullptr); }
  InterruptibleScope(const InterruptibleScope&) = delete;
  InterruptibleScope& operator=(const InterruptibleScope&) = delete;

 private:
  JobContext& job_;
};

// A submission as the kind's check sees it.
struct JobSubmission {
  std::optional<std::string> map;
  std::string request;   // the document to store, encoded (storage/document_codec.h)
  std::int64_t now_ns = 0;
};

struct JobKind {
  std::string name;         // "forget"
  std::string first_stage;  // the stage a job is in when it starts
  bool needs_map = false;   // submitted for one map (checked to exist) or for the whole file
  // Checks a submission before anything is queued; throws Error naming the field. May be empty.
  std::function<void(const JobSubmission&)> check;
  // Does the work. Returns the result document (encoded) to record with status succeeded, or nullopt when the runner recorded
  // its final status itself (JobContext::Record). Throws to fail the job.
  std::function<std::optional<std::string>(JobContext&)> run;
  // Appended to the error of a job that fails after it recorded a result (the work committed, a later stage failed).
  std::string note_when_failed_after_result;
};

class JobRegistry {
 public:
  // Throws Error(kConflict) when a kind of that name is registered already, kInvalidArgument when it has no runner.
  void Register(JobKind kind);
  // nullptr when no kind of that name is registered.
  std::shared_ptr<const JobKind> Find(std::string_view name) const;

 private:
  std::map<std::string, std::shared_ptr<const JobKind>, std::less<>> kinds_;
};

}  // namespace anchordb::services
