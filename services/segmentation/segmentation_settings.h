#pragma once
// The settings of the furniture segmentation capability (GET /v1/settings, --help).
#include "schema/settings.h"
#include "services/segmentation/furniture_segmentation_service.h"

namespace anchordb::services {

void BindSegmentationSettings(SettingsBinder& b, SegmentationSettings& s);

}  // namespace anchordb::services
