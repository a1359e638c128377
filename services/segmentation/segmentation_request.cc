// The stored form of a segmentation request (the job's request document) and its checks.
#include <nlohmann/json.hpp>

#include <cmath>

#include "schema/error.h"
#include "services/segmentation/furniture_segmentation_service.h"

namespace anchordb::services {

using Json = nlohmann::json;

std::string SegmentationRequestDocument(const SegmentationRequest& r) {
  const auto& p = r.params;
  Json j{{"source", r.source == SegmentationSource::kOctomap ? "octomap" : "keyframes"},
         {"keyframes", r.keyframes}, {"max_keyframes", r.max_keyframes}, {"max_range_m", r.max_range_m},
         {"match_iou", r.match_iou},
         {"params", {{"voxel_m", p.voxel_m}, {"plane_distance_m", p.plane_distance_m}, {"plane_iterations", p.plane_iterations},
                     {"max_planes", p.max_planes}, {"min_plane_points", p.min_plane_points},
                     {"axis_tolerance_rad", p.axis_tolerance_rad}, {"behind_margin_m", p.behind_margin_m},
                     {"max_behind_fraction", p.max_behind_fraction}, {"wall_min_width_m", p.wall_min_width_m},
                     {"wall_min_height_m", p.wall_min_height_m}, {"band_m", p.band_m}, {"outlier_radius_m", p.outlier_radius_m},
                     {"outlier_min_neighbours", p.outlier_min_neighbours}, {"cluster_tolerance_m", p.cluster_tolerance_m},
                     {"min_cluster_points", p.min_cluster_points}, {"contact_m", p.contact_m}, {"wall_reach_m", p.wall_reach_m},
                     {"core_radius_m", p.core_radius_m}, {"core_density", p.core_density}}}};
  if (r.shape_model) j["shape_model"] = *r.shape_model;
  return j.dump();
}

SegmentationRequest SegmentationRequestFromDocument(const std::string& text) {
  const Json j = Json::parse(text, nullptr, false);
  if (!j.is_object()) throw Error(ErrorCode::kInternal, "stored segmentation request is not JSON");
  SegmentationRequest r;
  r.source = j.value("source", std::string("keyframes")) == "octomap" ? SegmentationSource::kOctomap : SegmentationSource::kKeyframes;
  r.keyframes = j.value("keyframes", std::vector<std::int64_t>{});
  r.max_keyframes = j.value("max_keyframes", r.max_keyframes);
  r.max_range_m = j.value("max_range_m", r.max_range_m);
  r.match_iou = j.value("match_iou", r.match_iou);
  if (j.contains("shape_model")) r.shape_model = j["shape_model"].get<std::string>();
  const Json& p = j.value("params", Json::object());
  auto& q = r.params;
  q.voxel_m = p.value("voxel_m", q.voxel_m);
  q.plane_distance_m = p.value("plane_distance_m", q.plane_distance_m);
  q.plane_iterations = p.value("plane_iterations", q.plane_iterations);
  q.max_planes = p.value("max_planes", q.max_planes);
  q.min_plane_points = p.value("min_plane_points", q.min_plane_points);
  q.axis_tolerance_rad = p.value("axis_tolerance_rad", q.axis_tolerance_rad);
  q.behind_margin_m = p.value("behind_margin_m", q.behind_margin_m);
  q.max_behind_fraction = p.value("max_behind_fraction", q.max_behind_fraction);
  q.wall_min_width_m = p.value("wall_min_width_m", q.wall_min_width_m);
  q.wall_min_height_m = p.value("wall_min_height_m", q.wall_min_height_m);
  q.band_m = p.value("band_m", q.band_m);
  q.outlier_radius_m = p.value("outlier_radius_m", q.outlier_radius_m);
  q.outlier_min_neighbours = p.value("outlier_min_neighbours", q.outlier_min_neighbours);
  q.cluster_tolerance_m = p.value("cluster_tolerance_m", q.cluster_tolerance_m);
  q.min_cluster_points = p.value("min_cluster_points", q.min_cluster_points);
  q.contact_m = p.value("contact_m", q.contact_m);
  q.wall_reach_m = p.value("wall_reach_m", q.wall_reach_m);
  q.core_radius_m = p.value("core_radius_m", q.core_radius_m);
  q.core_density = p.value("core_density", q.core_density);
  return r;
}

void CheckSegmentationRequest(const SegmentationRequest& r) {
  if (r.keyframes.size() > 10000) throw Error(ErrorCode::kPayloadTooLarge, "at most 10000 keyframes", "keyframes");
  for (std::size_t i = 0; i < r.keyframes.size(); ++i) {
    if (r.keyframes[i] < 1) throw Error(ErrorCode::kInvalidArgument, "keyframe ids are positive", "keyframes[" + std::to_string(i) + "]");
  }
  if (r.source == SegmentationSource::kOctomap && !r.keyframes.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "keyframes are a keyframes source's; the octomap source takes none", "keyframes");
  }
  if (r.max_keyframes < 1 || r.max_keyframes > 10000) throw Error(ErrorCode::kUnprocessable, "max_keyframes must be in [1, 10000]", "max_keyframes");
  if (!(r.max_range_m > 0.0 && r.max_range_m <= 100.0)) throw Error(ErrorCode::kUnprocessable, "max_range_m must be in (0, 100] m", "max_range_m");
  if (!(r.match_iou > 0.0 && r.match_iou <= 1.0)) throw Error(ErrorCode::kUnprocessable, "match_iou must be in (0, 1]", "match_iou");
  if (r.shape_model && r.shape_model->empty()) throw Error(ErrorCode::kInvalidArgument, "shape_model must name a model", "shape_model");
  engine::segmentation::SegmentFurniture({}, r.params);  // checks the parameters (an empty cloud does nothing else)
}

}  // namespace anchordb::services
