#pragma once
// TRANSITIONAL (issue 11): SceneService still answers frames in JSON and puts the keyframe analysis into it. This
// copy of api::KeyframeAnalysisJson (api/event_json.h, the serialiser to use) goes when SceneService's results are
// typed and api/ serialises them.
#include "services/common/transitional_json.h"
#include "services/scene/keyframe_listener.h"

namespace anchordb::services {

Json TransitionalAnalysisJson(const KeyframeAnalysis& analysis);

}  // namespace anchordb::services
