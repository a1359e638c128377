#pragma once
// The settings of change detection, instance matching and the lost-key rule, bound once to EventSettings.
#include "schema/settings.h"
#include "services/events/event_service.h"

namespace anchordb::services {

void BindEventSettings(SettingsBinder& b, EventSettings& events);

}  // namespace anchordb::services
