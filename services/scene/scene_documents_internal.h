#pragma once
// Internal to the scene capability: the JSON of a scene model's camera, pose and params as the responses show them
// (stored as typed columns since migration 0017), and the merge report, still a JSON document of the row (issue 30:
// next to become typed). api/scene_json.cc writes them with these functions (one definition of the format). Not
// part of the service's interface: it includes nlohmann-json.
#include "schema/json_io.h"
#include "services/scene/scene_types.h"

namespace anchordb::services::scene_documents {

using json::Json;

Json CameraDocument(const PinholeIntrinsics& K);

// {"position":[x,y,z],"orientation":[qx,qy,qz,qw]}.
Json PoseDocument(const Pose3& pose);

Json ParamsDocument(const SceneParams& params);

// Keys that a report of an older release lacks take their defaults.
Json MergeReportDocument(const MergeReport& report);
MergeReport MergeReportFromDocument(const Json& j);

}  // namespace anchordb::services::scene_documents
