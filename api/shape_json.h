#pragma once
// JSON of 3D shape models (SPEC §5: POST /v1/shape-models, GET /v1/shape-models[/{name}], :classify, :detect).
#include "api/http_api.h"
#include "services/shapes/shape_types.h"

namespace anchordb::api {

// The multipart `spec` part: {"name", "params"?: {voxel_m, normal_radius_m, boundary_angle_rad, keypoint_spacing_m,
// shot_radius_m, codebook_size, activated_words, azimuth_bins, polar_bins, sphere_radius_m, detection_spacing_m,
// accept_fraction, merge_distance_m, max_keypoints, seed}, "mesh_views"?: 12, "categories"?: [..],
// "samples": [{"part": "<name of a multipart part>", "category", "kind": "cloud" | "mesh"}]}. `part_body` returns a
// part's content, or nullptr when the request has no such part.
services::TrainShapeModelRequest ParseTrainShapeModelRequest(
    const Json& spec, const std::function<const std::string*(const std::string&)>& part_body);
Json ToJson(const services::ShapeModelView& v);
Json ToJson(const services::ShapeClassification& c);
Json ToJson(const services::ShapeDetections& d);

}  // namespace anchordb::api
