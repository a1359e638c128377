#pragma once
// The routes of one capability (GridService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/grid/grid_service.h"

namespace anchordb::api {

void RegisterGridRoutes(Router& router, services::GridService& service);

}  // namespace anchordb::api
