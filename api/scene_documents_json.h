#pragma once
// The JSON of what a scene model response shows beyond its plain fields: the camera, the pose, the parameters and the
// merge report (keys a report of an older release lacks were given their defaults when it was read). The one
// definition of their format, for api/scene_json.cc.
#include "schema/json_io.h"
#include "services/scene/scene_types.h"

namespace anchordb::api::scene_documents {

using json::Json;

Json CameraDocument(const PinholeIntrinsics& K);
// {"position":[x,y,z],"orientation":[qx,qy,qz,qw]}.
Json PoseDocument(const Pose3& pose);
Json ParamsDocument(const services::SceneParams& params);
Json MergeReportDocument(const services::MergeReport& report);

}  // namespace anchordb::api::scene_documents
