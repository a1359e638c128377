#pragma once
// The routes of one capability (SceneService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/scene/scene_service.h"

namespace anchordb::api {

void RegisterSceneRoutes(Router& router, services::SceneService& service);

}  // namespace anchordb::api
