#pragma once
// The routes of furniture segmentation (FurnitureSegmentationService, thesis 5.3.1): a segmentation job and the
// furniture instances it found, with their clouds.
#include "api/router.h"
#include "services/segmentation/furniture_segmentation_service.h"

namespace anchordb::api {

void RegisterSegmentationRoutes(Router& router, services::FurnitureSegmentationService& service);

}  // namespace anchordb::api
