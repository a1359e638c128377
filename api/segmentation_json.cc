#include "api/segmentation_json.h"

namespace anchordb::api {
namespace {

Json OrNull(const std::optional<std::string>& v) { return v ? Json(*v) : Json(nullptr); }
Json OrNull(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

}  // namespace

Json ToJson(const storage::SegmentationJobRequest& r) {
  Json params = Json::object();
  for (const auto& [name, value] : r.params) params[name] = value;
  Json j{{"source", r.source},       {"use_stored_shape_model", r.use_stored_shape_model},
         {"keyframes", r.keyframes}, {"max_keyframes", r.max_keyframes},
         {"max_range_m", r.max_range_m}, {"match_iou", r.match_iou},
         {"params", params}};
  if (r.shape_model) j["shape_model"] = *r.shape_model;
  if (r.staging) j["staging"] = *r.staging;
  return j;
}

Json ToJson(const storage::SegmentationJobResult& r) {
  Json segments = Json::array();
  for (const storage::SegmentationJobSegment& s : r.segments) {
    segments.push_back({{"action", s.action}, {"furniture", s.furniture}, {"label", s.label},
                        {"label_probability", s.label_probability}, {"classifier", s.classifier},
                        {"position_m", {s.x_m, s.y_m}}, {"extent_m", {s.extent_x_m, s.extent_y_m}},
                        {"yaw_rad", s.yaw_rad}, {"height_m", s.height_m}, {"points", s.points},
                        {"cloud", "/v1/maps/" + r.map_id + "/furniture/" + std::to_string(s.furniture) + "/cloud"}});
  }
  return {{"source", r.source}, {"shape_model", OrNull(r.shape_model)}, {"octomap_truncated", r.octomap_truncated},
          {"bridges_cut", r.bridges_cut}, {"input_points", r.input_points}, {"thinned_points", r.thinned_points},
          {"remaining_points", r.remaining_points}, {"planes", r.planes}, {"small_clusters", r.small_clusters},
          {"flying_dropped", r.flying_dropped}, {"floor_z_m", OrNull(r.floor_z_m)}, {"segments", segments},
          {"seconds", r.seconds}};
}

}  // namespace anchordb::api
