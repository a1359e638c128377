#pragma once
// The settings of scene models and their merging, bound once to the fields of their options structs.
#include "schema/settings.h"
#include "services/scene/scene_service.h"

namespace anchordb::services {

void BindSceneSettings(SettingsBinder& b, SceneLimits& scene, MergeSettings& merge);

}  // namespace anchordb::services
