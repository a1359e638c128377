#pragma once
// JSON of a shape model's stored documents (storage/shape_documents.h, through the service's types): its options and
// report (GET /v1/shape-models) and the shape_model_train job's request and result (GET /v1/jobs).
#include "schema/json_io.h"
#include "services/shapes/shape_types.h"

namespace anchordb::api {

// {"name", "params": {the parameters a request may set}, "mesh_views", "parts": [{"part", "category", "kind":
// "cloud" with "points" | "mesh" with "triangles"}]}
json::Json ToJson(const storage::ShapeModelOptionsRecord& options);
// {"categories": [{"category", "samples", "keypoints"}], "samples", "keypoints", "codebook_size", "non_empty_bins",
// "mesh_views", "train_seconds"}
json::Json ToJson(const storage::ShapeModelReportRecord& report);
// The options and {"staging"}.
json::Json ToJson(const storage::ShapeTrainingRequestRecord& request);
// {"name", "samples", "keypoints", "train_seconds"}
json::Json ToJson(const storage::ShapeTrainingResultRecord& result);

// The writers of the shape_model_train job's documents (api/job_json.h).
void RegisterShapeJobDocumentWriters();

}  // namespace anchordb::api
