// The stored documents of the segmentation capability -- the job's request and result documents and a furniture
// instance's evidence list -- and the request's checks: the one file of services/segmentation that writes JSON.
#include <nlohmann/json.hpp>

#include <cmath>

#include "engine/cloud/cloud_io.h"
#include "schema/error.h"
#include "services/segmentation/furniture_segmentation_service.h"

namespace anchordb::services {

using Json = nlohmann::json;

namespace {

const char* SourceName(SegmentationSource s) {
  switch (s) {
    case SegmentationSource::kOctomap: return "octomap";
    case SegmentationSource::kCloud: return "cloud";
    case SegmentationSource::kKeyframes: return "keyframes";
  }
  return "keyframes";
}

}  // namespace

std::string SegmentationRequestDocument(const SegmentationRequest& r, std::optional<std::int64_t> staging) {
  const auto& p = r.params;
  Json j{{"source", SourceName(r.source)}, {"use_stored_shape_model", r.use_stored_shape_model},
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
  if (staging) j["staging"] = *staging;
  return j.dump();
}

SegmentationRequest SegmentationRequestFromDocument(const std::string& text, std::optional<std::int64_t>* staging) {
  const Json j = Json::parse(text, nullptr, false);
  if (!j.is_object()) throw Error(ErrorCode::kInternal, "stored segmentation request is not JSON");
  SegmentationRequest r;
  const std::string source = j.value("source", std::string("keyframes"));
  r.source = source == "octomap" ? SegmentationSource::kOctomap
             : source == "cloud" ? SegmentationSource::kCloud : SegmentationSource::kKeyframes;
  r.use_stored_shape_model = j.value("use_stored_shape_model", true);
  if (staging) *staging = j.contains("staging") ? std::optional<std::int64_t>(j["staging"].get<std::int64_t>()) : std::nullopt;
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
  if (r.source != SegmentationSource::kKeyframes && !r.keyframes.empty()) {
    throw Error(ErrorCode::kInvalidArgument, std::string("keyframes are a keyframes source's; the ") + SourceName(r.source) + " source takes none", "keyframes");
  }
  if (r.max_keyframes < 1 || r.max_keyframes > 10000) throw Error(ErrorCode::kUnprocessable, "max_keyframes must be in [1, 10000]", "max_keyframes");
  if (!(r.max_range_m > 0.0 && r.max_range_m <= 100.0)) throw Error(ErrorCode::kUnprocessable, "max_range_m must be in (0, 100] m", "max_range_m");
  if (!(r.match_iou > 0.0 && r.match_iou <= 1.0)) throw Error(ErrorCode::kUnprocessable, "match_iou must be in (0, 1]", "match_iou");
  if (r.shape_model && r.shape_model->empty()) throw Error(ErrorCode::kInvalidArgument, "shape_model must name a model", "shape_model");
  engine::segmentation::SegmentFurniture({}, r.params);  // checks the parameters (an empty cloud does nothing else)
}

}  // namespace anchordb::services

namespace anchordb::services {

std::vector<Eigen::Vector3f> DecodeRoomCloud(const std::string& bytes, bool skip_nonfinite, std::size_t max_points) {
  if (bytes.empty()) throw Error(ErrorCode::kUnprocessable, "the room cloud is empty (send a PCD or PLY body)", "body");
  engine::DecodedCloud cloud;
  try {
    cloud = engine::DecodeCloud(bytes, max_points);
  } catch (const Error& e) {
    throw Error(e.code(), e.what(), "body");
  }
  std::vector<Eigen::Vector3f> out;
  out.reserve(cloud.points.size());
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    if (cloud.points[i].allFinite()) out.push_back(cloud.points[i]);
    else if (!skip_nonfinite) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " is not finite (NaN or infinite; skip_nonfinite=true leaves such points out)", "body");
    }
  }
  if (out.empty()) throw Error(ErrorCode::kUnprocessable, "the room cloud has no finite points", "body");
  return out;
}

std::string SegmentationResultDocument(const SegmentationOutcome& out, const std::string& map) {
  Json segments = Json::array();
  for (const SegmentOutcome& s : out.segments) {
    segments.push_back({{"action", s.action}, {"furniture", s.instance.id}, {"label", s.instance.label},
                        {"label_probability", s.instance.label_probability}, {"classifier", s.instance.classifier},
                        {"position_m", {s.instance.position_m.x(), s.instance.position_m.y()}},
                        {"extent_m", {s.instance.extent_m.x(), s.instance.extent_m.y()}}, {"yaw_rad", s.instance.yaw_rad},
                        {"height_m", s.instance.height_m}, {"points", s.instance.points},
                        {"cloud", "/v1/maps/" + map + "/furniture/" + std::to_string(s.instance.id) + "/cloud"}});
  }
  return Json{{"source", out.source}, {"shape_model", out.shape_model ? Json(*out.shape_model) : Json()},
              {"octomap_truncated", out.octomap_truncated}, {"bridges_cut", out.bridges_cut},
              {"input_points", out.input_points}, {"thinned_points", out.thinned_points},
              {"remaining_points", out.remaining_points}, {"planes", out.planes}, {"small_clusters", out.small_clusters},
              {"flying_dropped", out.flying_dropped}, {"floor_z_m", out.floor_z_m ? Json(*out.floor_z_m) : Json()},
              {"segments", segments}, {"seconds", out.seconds}}
      .dump();
}

std::string EvidenceDocument(const std::vector<std::int64_t>& keyframes) { return Json(keyframes).dump(); }

std::vector<std::int64_t> EvidenceFromDocument(const std::string& text) {
  const Json j = Json::parse(text, nullptr, false);
  std::vector<std::int64_t> out;
  if (!j.is_array()) return out;
  for (const Json& id : j) {
    if (id.is_number_integer()) out.push_back(id.get<std::int64_t>());
  }
  return out;
}

}  // namespace anchordb::services
