#include "api/shape_documents_json.h"

#include "api/job_json.h"

namespace anchordb::api {

using json::Json;

Json ToJson(const storage::ShapeModelOptionsRecord& o) {
  const storage::ShapeModelParamsRecord& p = o.params;
  // The size term's parameters (size_weight, size_bandwidth, size_floor) are not settable over HTTP: left out, so
  // that these params can be sent again as a request's.
  const Json params = {{"voxel_m", p.voxel_m}, {"normal_radius_m", p.normal_radius_m},
                       {"boundary_angle_rad", p.boundary_angle_rad}, {"keypoint_spacing_m", p.keypoint_spacing_m},
                       {"shot_radius_m", p.shot_radius_m}, {"codebook_size", p.codebook_size},
                       {"activated_words", p.activated_words}, {"azimuth_bins", p.azimuth_bins},
                       {"polar_bins", p.polar_bins}, {"sphere_radius_m", p.sphere_radius_m},
                       {"detection_spacing_m", p.detection_spacing_m}, {"accept_fraction", p.accept_fraction},
                       {"merge_distance_m", p.merge_distance_m}, {"max_keypoints", p.max_keypoints}, {"seed", p.seed}};
  Json parts = Json::array();
  for (const auto& part : o.parts) {
    parts.push_back({{"part", part.part}, {"category", part.category}, {"kind", part.mesh ? "mesh" : "cloud"},
                     {part.mesh ? "triangles" : "points", part.count}});
  }
  return {{"name", o.name}, {"params", params}, {"mesh_views", o.mesh_views}, {"parts", parts}};
}

Json ToJson(const storage::ShapeModelReportRecord& r) {
  Json categories = Json::array();
  for (const auto& c : r.categories) {
    categories.push_back({{"category", c.category}, {"samples", c.samples}, {"keypoints", c.keypoints}});
  }
  return {{"categories", categories}, {"samples", r.samples}, {"keypoints", r.keypoints},
          {"codebook_size", r.codebook_size}, {"non_empty_bins", r.non_empty_bins}, {"mesh_views", r.mesh_views},
          {"train_seconds", r.train_seconds}};
}

Json ToJson(const storage::ShapeTrainingRequestRecord& r) {
  Json j = ToJson(r.options);
  j["staging"] = r.staging;
  return j;
}

Json ToJson(const storage::ShapeTrainingResultRecord& r) {
  return {{"name", r.name}, {"samples", r.samples}, {"keypoints", r.keypoints}, {"train_seconds", r.train_seconds}};
}

void RegisterShapeJobDocumentWriters() {
  RegisterJobDocumentWriters(
      "shape_model_train",
      {[](const std::string& d, const std::string& what) { return ToJson(storage::DecodeShapeTrainingRequest(d, what)); },
       [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeShapeTrainingResult(d, what)); }});
}

}  // namespace anchordb::api
