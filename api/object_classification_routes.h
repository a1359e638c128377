#pragma once
// Routes of object classification (issue 15 "Object classification"; SPEC §5: POST .../instances/{id}:classify).
#include "api/router.h"
#include "services/classification/classifier_service.h"

namespace anchordb::api {

void RegisterObjectClassificationRoutes(Router& router, services::ClassifierService& classifiers);

}  // namespace anchordb::api
