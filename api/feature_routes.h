#pragma once
// Routes of anchored features, codebooks and bags of words (SPEC §4.6, §5).
#include "api/router.h"
#include "services/features/feature_service.h"

namespace anchordb::api {

void RegisterFeatureRoutes(Router& router, services::FeatureService& features);

}  // namespace anchordb::api
