#pragma once
// Internal to the scene capability: the JSON documents a scene model's row stores (camera, pose, params, merge
// report) and their typed forms. The service stores and loads them; the responses show them as stored, so
// api/scene_json.cc writes them with the same functions (one definition of the format). Not part of the service's
// interface: it includes nlohmann-json.
#include "schema/json_io.h"
#include "services/scene/scene_types.h"

namespace anchordb::services::scene_documents {

using json::Json;

Json CameraDocument(const PinholeIntrinsics& K);
PinholeIntrinsics CameraFromDocument(const Json& j);

// {"position":[x,y,z],"orientation":[qx,qy,qz,qw]}; read back exactly as written (no renormalisation).
Json PoseDocument(const Pose3& pose);
Pose3 PoseFromDocument(const Json& j);

Json ParamsDocument(const SceneParams& params);
SceneParams ParamsFromDocument(const Json& j);

// Keys that a report of an older release lacks take their defaults.
Json MergeReportDocument(const MergeReport& report);
MergeReport MergeReportFromDocument(const Json& j);

}  // namespace anchordb::services::scene_documents
