#pragma once
// Every capability's routes on one router (the composition the server and the OpenAPI test share).
#include "api/router.h"
#include "services/capabilities.h"

namespace anchordb::api {

void RegisterAllRoutes(Router& router, services::Capabilities& capabilities);

}  // namespace anchordb::api
