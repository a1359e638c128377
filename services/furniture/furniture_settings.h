#pragma once
// The settings of furniture graphs and grounding, bound once to FurnitureSettings.
#include "schema/settings.h"
#include "services/furniture/furniture_service.h"

namespace anchordb::services {

void BindFurnitureSettings(SettingsBinder& b, FurnitureSettings& furniture);

}  // namespace anchordb::services
