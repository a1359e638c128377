#pragma once
// The settings of the grid capability, bound once to the fields of its options structs (schema/settings.h).
#include "schema/settings.h"
#include "services/grid/grid_service.h"

namespace anchordb::services {

void BindGridSettings(SettingsBinder& b, ServiceLimits& limits, GridDefaults& grid);

}  // namespace anchordb::services
