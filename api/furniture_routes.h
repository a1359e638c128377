#pragma once
// The routes of one capability (FurnitureService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/furniture/furniture_service.h"

namespace anchordb::api {

void RegisterFurnitureRoutes(Router& router, services::FurnitureService& service);

}  // namespace anchordb::api
