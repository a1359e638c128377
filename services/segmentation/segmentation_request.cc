// The stored documents of the segmentation capability -- the job's request and result, typed records of
// storage/segmentation_documents.h -- and the request's checks.
#include <cmath>
#include <map>
#include <type_traits>

#include "engine/cloud/cloud_io.h"
#include "schema/error.h"
#include "services/segmentation/furniture_segmentation_service.h"
#include "storage/segmentation_documents.h"

namespace anchordb::services {

namespace {

const char* SourceName(SegmentationSource s) {
  switch (s) {
    case SegmentationSource::kOctomap: return "octomap";
    case SegmentationSource::kCloud: return "cloud";
    case SegmentationSource::kKeyframes: return "keyframes";
  }
  return "keyframes";
}

SegmentationSource SourceOf(const std::string& name) {
  if (name == "octomap") return SegmentationSource::kOctomap;
  if (name == "cloud") return SegmentationSource::kCloud;
  return SegmentationSource::kKeyframes;
}

// Every stored segmentation parameter with its name: the one list both directions use.
template <typename Params, typename Visit>
void ForEachParam(Params& p, Visit&& visit) {
  visit("voxel_m", p.voxel_m);
  visit("plane_distance_m", p.plane_distance_m);
  visit("plane_iterations", p.plane_iterations);
  visit("max_planes", p.max_planes);
  visit("min_plane_points", p.min_plane_points);
  visit("axis_tolerance_rad", p.axis_tolerance_rad);
  visit("behind_margin_m", p.behind_margin_m);
  visit("max_behind_fraction", p.max_behind_fraction);
  visit("wall_min_width_m", p.wall_min_width_m);
  visit("wall_min_height_m", p.wall_min_height_m);
  visit("band_m", p.band_m);
  visit("outlier_radius_m", p.outlier_radius_m);
  visit("outlier_min_neighbours", p.outlier_min_neighbours);
  visit("cluster_tolerance_m", p.cluster_tolerance_m);
  visit("min_cluster_points", p.min_cluster_points);
  visit("contact_m", p.contact_m);
  visit("wall_reach_m", p.wall_reach_m);
  visit("core_radius_m", p.core_radius_m);
  visit("core_density", p.core_density);
}

}  // namespace

std::string SegmentationRequestDocument(const SegmentationRequest& r, std::optional<std::int64_t> staging) {
  storage::SegmentationJobRequest d;
  d.source = SourceName(r.source);
  d.keyframes = r.keyframes;
  d.max_keyframes = r.max_keyframes;
  d.max_range_m = r.max_range_m;
  d.shape_model = r.shape_model;
  d.use_stored_shape_model = r.use_stored_shape_model;
  d.match_iou = r.match_iou;
  d.staging = staging;
  ForEachParam(r.params, [&](const char* name, const auto& value) { d.params.emplace_back(name, static_cast<double>(value)); });
  return storage::EncodeSegmentationRequest(d);
}

SegmentationRequest SegmentationRequestFromDocument(const std::string& encoded, std::optional<std::int64_t>* staging) {
  const storage::SegmentationJobRequest d = storage::DecodeSegmentationRequest(encoded, "a segmentation job's request");
  SegmentationRequest r;
  r.source = SourceOf(d.source);
  r.keyframes = d.keyframes;
  r.max_keyframes = static_cast<int>(d.max_keyframes);
  r.max_range_m = d.max_range_m;
  r.shape_model = d.shape_model;
  r.use_stored_shape_model = d.use_stored_shape_model;
  r.match_iou = d.match_iou;
  if (staging) *staging = d.staging;
  const std::map<std::string, double> stored(d.params.begin(), d.params.end());
  ForEachParam(r.params, [&](const char* name, auto& value) {
    if (const auto it = stored.find(name); it != stored.end()) value = static_cast<std::decay_t<decltype(value)>>(it->second);
  });
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
  storage::SegmentationJobResult d;
  d.map_id = map;
  d.source = out.source;
  d.shape_model = out.shape_model;
  d.octomap_truncated = out.octomap_truncated;
  d.bridges_cut = out.bridges_cut;
  d.input_points = static_cast<std::int64_t>(out.input_points);
  d.thinned_points = static_cast<std::int64_t>(out.thinned_points);
  d.remaining_points = static_cast<std::int64_t>(out.remaining_points);
  d.planes = out.planes;
  d.small_clusters = out.small_clusters;
  d.flying_dropped = out.flying_dropped;
  d.floor_z_m = out.floor_z_m;
  for (const SegmentOutcome& s : out.segments) {
    const FurnitureInstanceView& f = s.instance;
    d.segments.push_back({s.action, f.id, f.label, f.label_probability, f.classifier, f.position_m.x(), f.position_m.y(),
                          f.extent_m.x(), f.extent_m.y(), f.yaw_rad, f.height_m, f.points});
  }
  d.seconds = out.seconds;
  return storage::EncodeSegmentationResult(d);
}

}  // namespace anchordb::services
