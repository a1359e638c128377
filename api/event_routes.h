#pragma once
// The routes of one capability (EventService): thin handlers that parse, call the service, serialise.
#include "api/router.h"
#include "services/events/analysis_queue.h"
#include "services/events/event_service.h"

namespace anchordb::api {

void RegisterEventRoutes(Router& router, services::EventService& service);
// GET /v1/maps/{map}/analysis.
void RegisterAnalysisRoutes(Router& router, services::AnalysisQueue& queue);

}  // namespace anchordb::api
