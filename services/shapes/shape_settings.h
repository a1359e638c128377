#pragma once
// The settings of the 3D shape models capability (GET /v1/settings, --help).
#include "schema/settings.h"
#include "services/shapes/shape_service.h"

namespace anchordb::services {

void BindShapeSettings(SettingsBinder& b, ShapeSettings& s);

}  // namespace anchordb::services
