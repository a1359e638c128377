#pragma once
// A job's status as the jobs table stores it: one enum and its one table of stored names ("queued", "running",
// "succeeded", "failed"; the CHECK of migration 0004), which the API serves unchanged.
#include <cstdint>
#include <string_view>

namespace anchordb::storage {

enum class JobStatus : std::uint8_t { kQueued, kRunning, kSucceeded, kFailed };

const char* JobStatusName(JobStatus status);
// A stored name back; Error(kInternal) for a name the table does not hold (a corrupt row).
JobStatus JobStatusFromName(std::string_view name);

}  // namespace anchordb::storage
