#pragma once
// JSON <-> typed for the scene routes: the body that opens a scene model, and every response of
// api/scene_routes.cc. The camera, pose, params and merge report a response shows are written by
// api/scene_documents_json.h, the one definition of their format.
#include <vector>

#include "schema/json_io.h"
#include "services/scene/scene_types.h"

namespace anchordb::api::scene_json {

using json::Json;

// {"camera": {width, height, fx, fy, cx, cy}, "pose": {position, orientation}, "params"?: {beta, dynamic_mode,
// depth_scale, merge_strategy}, "merge"?: bool, "stamp"?}. kInvalidArgument / kInvalidJson for what is not of this
// form (the value ranges are the service's to check).
services::OpenSceneRequest ParseOpenScene(const Json& body);

Json SceneJson(const services::SceneInfo& scene, bool with_keyframes);
Json SceneListJson(const std::vector<services::SceneInfo>& scenes);
Json FrameJson(const services::FrameResult& result);
Json KeyframeJson(const services::KeyframeResult& result);
Json CloseJson(const services::CloseResult& result);
Json LayerSummaryJson(const services::SceneLayerSummary& summary);
Json KeyframeInfoJson(const services::KeyframeInfo& keyframe);

}  // namespace anchordb::api::scene_json
