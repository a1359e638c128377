#pragma once
// The routes of one capability (JobService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/jobs/job_service.h"

namespace anchordb::api {

void RegisterJobRoutes(Router& router, services::JobService& service);

}  // namespace anchordb::api
