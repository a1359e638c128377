#pragma once
// The routes of the octomap capability (OctomapService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/octomap/octomap_service.h"

namespace anchordb::api {

void RegisterOctomapRoutes(Router& router, services::OctomapService& service);

}  // namespace anchordb::api
