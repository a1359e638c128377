#include "api/routes.h"
#include "api/segmentation_routes.h"

#include "api/audit_routes.h"
#include "api/classifier_routes.h"
#include "api/console_routes.h"
#include "api/event_routes.h"
#include "api/feature_routes.h"
#include "api/furniture_routes.h"
#include "api/grid_routes.h"
#include "api/job_routes.h"
#include "api/object_classification_routes.h"
#include "api/octomap_routes.h"
#include "api/scene_routes.h"
#include "api/shape_routes.h"
#include "api/stream_routes.h"

namespace anchordb::api {

void RegisterAllRoutes(Router& router, services::Capabilities& c) {
  RegisterGridRoutes(router, c.grid);
  RegisterSceneRoutes(router, c.scenes);
  RegisterFurnitureRoutes(router, c.furniture);
  RegisterEventRoutes(router, c.events);
  RegisterAnalysisRoutes(router, c.analysis);
  RegisterJobRoutes(router, c.jobs);
  RegisterOctomapRoutes(router, c.octomap);
  RegisterFeatureRoutes(router, c.features);
  RegisterClassifierRoutes(router, c.classifiers);
  RegisterObjectClassificationRoutes(router, c.classifiers);
  RegisterShapeRoutes(router, c.shapes);
  RegisterSegmentationRoutes(router, c.segmentation);
  RegisterStreamRoutes(router, c.events, c.jobs);
  RegisterConsoleRoutes(router);
  RegisterAuditRoutes(router, c.audit);  // last: it observes the routes above
}

}  // namespace anchordb::api
