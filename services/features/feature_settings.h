#pragma once
// The settings of the anchored features capability (GET /v1/settings, --help).
#include "schema/settings.h"
#include "services/features/feature_types.h"

namespace anchordb::services {

void BindFeatureSettings(SettingsBinder& b, FeatureSettings& f);

}  // namespace anchordb::services
