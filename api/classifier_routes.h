#pragma once
// Routes of trained E-SAMME classifiers (SPEC §4.6, §5).
#include "api/router.h"
#include "services/classification/classifier_service.h"

namespace anchordb::api {

void RegisterClassifierRoutes(Router& router, services::ClassifierService& classifiers);

}  // namespace anchordb::api
