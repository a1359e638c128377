#include "services/jobs/job_registry.h"

#include "schema/error.h"

namespace anchordb::services {

void JobRegistry::Register(JobKind kind) {
  if (kind.name.empty() || !kind.run) throw Error(ErrorCode::kInvalidArgument, "a job kind needs a name and a runner", "kind");
  const std::string name = kind.name;
  if (!kinds_.emplace(name, std::make_shared<const JobKind>(std::move(kind))).second) {
    throw Error(ErrorCode::kConflict, "job kind '" + name + "' is registered already", "kind");
  }
}

std::shared_ptr<const JobKind> JobRegistry::Find(std::string_view name) const {
  const auto it = kinds_.find(name);
  return it == kinds_.end() ? nullptr : it->second;
}

}  // namespace anchordb::services
