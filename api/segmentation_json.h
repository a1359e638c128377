#pragma once
// JSON of a furniture segmentation job's stored request and result (GET /v1/jobs/{id}).
#include "schema/json_io.h"
#include "services/segmentation/segmentation_types.h"

namespace anchordb::api {

using json::Json;

// {source, use_stored_shape_model, keyframes, max_keyframes, max_range_m, match_iou, params: {name: value}, shape_model?,
// staging?}
Json ToJson(const storage::SegmentationJobRequest& request);
// {source, shape_model, octomap_truncated, bridges_cut, input_points, thinned_points, remaining_points, planes,
// small_clusters, flying_dropped, floor_z_m, segments: [{action, furniture, label, label_probability, classifier,
// position_m, extent_m, yaw_rad, height_m, points, cloud}], seconds}; each segment names its cloud's route.
Json ToJson(const storage::SegmentationJobResult& result);

}  // namespace anchordb::api
