// Furniture segmentation routes: POST .../furniture:segment (202 job), GET .../furniture, .../furniture/{id},
// .../furniture/{id}/cloud.
#include "api/segmentation_routes.h"

#include "api/exported_bytes_http.h"
#include "api/http_api.h"
#include "api/job_json.h"
#include "api/octomap_json.h"
#include "api/route_params.h"
#include "api/segmentation_json.h"
#include "schema/error.h"
#include "schema/json_io.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

SegmentationRequest ParseSegmentationRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"source", "keyframes", "max_keyframes", "max_range_m", "shape_model", "use_stored_shape_model",
                                  "match_iou", "params"});
  SegmentationRequest r;
  if (const auto source = json::OptionalString(body, "source", 16)) {
    if (*source == "octomap") r.source = SegmentationSource::kOctomap;
    else if (*source == "cloud") {
      throw Error(ErrorCode::kInvalidArgument, "the cloud source takes the room cloud as the body (Content-Type application/x-pcd, "
                  "application/x-ply or application/octet-stream), not JSON", "source");
    } else if (*source != "keyframes") throw Error(ErrorCode::kInvalidArgument, "source must be keyframes or octomap", "source");
  }
  if (body.contains("use_stored_shape_model")) {
    if (!body["use_stored_shape_model"].is_boolean()) throw Error(ErrorCode::kInvalidArgument, "use_stored_shape_model must be true or false", "use_stored_shape_model");
    r.use_stored_shape_model = body["use_stored_shape_model"].get<bool>();
  }
  if (body.contains("keyframes")) {
    const Json& k = body["keyframes"];
    if (!k.is_array()) throw Error(ErrorCode::kInvalidArgument, "keyframes must be an array of keyframe ids", "keyframes");
    if (k.size() > 10000) throw Error(ErrorCode::kPayloadTooLarge, "at most 10000 keyframes", "keyframes");
    for (std::size_t i = 0; i < k.size(); ++i) {
      if (!k[i].is_number_integer()) throw Error(ErrorCode::kInvalidArgument, "a keyframe id is an integer", "keyframes[" + std::to_string(i) + "]");
      r.keyframes.push_back(k[i].get<std::int64_t>());
    }
  }
  r.max_keyframes = static_cast<int>(json::IntegerOr(body, "max_keyframes", r.max_keyframes));
  r.max_range_m = json::FiniteNumberOr(body, "max_range_m", r.max_range_m);
  r.match_iou = json::FiniteNumberOr(body, "match_iou", r.match_iou);
  r.shape_model = json::OptionalString(body, "shape_model", 64);
  if (body.contains("params")) {
    const Json& p = body["params"];
    if (!p.is_object()) throw Error(ErrorCode::kInvalidArgument, "params must be an object", "params");
    json::RejectUnknownKeys(p, {"voxel_m", "plane_distance_m", "cluster_tolerance_m", "min_cluster_points", "contact_m",
                                "band_m", "wall_min_width_m", "wall_min_height_m", "wall_reach_m", "core_radius_m",
                                "core_density"}, "params");
    auto& q = r.params;
    q.voxel_m = json::FiniteNumberOr(p, "voxel_m", q.voxel_m, "params");
    q.plane_distance_m = json::FiniteNumberOr(p, "plane_distance_m", q.plane_distance_m, "params");
    q.cluster_tolerance_m = json::FiniteNumberOr(p, "cluster_tolerance_m", q.cluster_tolerance_m, "params");
    const std::int64_t min_points = json::IntegerOr(p, "min_cluster_points", static_cast<std::int64_t>(q.min_cluster_points), "params");
    if (min_points < 1 || min_points > 10'000'000) throw Error(ErrorCode::kUnprocessable, "min_cluster_points must be in [1, 1e7]", "params.min_cluster_points");
    q.min_cluster_points = static_cast<std::size_t>(min_points);
    q.contact_m = json::FiniteNumberOr(p, "contact_m", q.contact_m, "params");
    q.band_m = json::FiniteNumberOr(p, "band_m", q.band_m, "params");
    q.wall_min_width_m = json::FiniteNumberOr(p, "wall_min_width_m", q.wall_min_width_m, "params");
    q.wall_min_height_m = json::FiniteNumberOr(p, "wall_min_height_m", q.wall_min_height_m, "params");
    q.wall_reach_m = json::FiniteNumberOr(p, "wall_reach_m", q.wall_reach_m, "params");
    q.core_radius_m = json::FiniteNumberOr(p, "core_radius_m", q.core_radius_m, "params");
    q.core_density = json::FiniteNumberOr(p, "core_density", q.core_density, "params");
  }
  return r;
}

// A PCD or PLY body: the room cloud itself (the cloud source); the options then come as query parameters.
bool IsCloudBody(const httplib::Request& req) {
  const std::string type = req.get_header_value("Content-Type");
  return type.rfind("application/x-pcd", 0) == 0 || type.rfind("application/x-ply", 0) == 0 ||
         type.rfind("application/octet-stream", 0) == 0;
}

SegmentationRequest ParseCloudSegmentationRequest(const httplib::Request& req) {
  SegmentationRequest r;
  r.source = SegmentationSource::kCloud;
  r.cloud_bytes = req.body;
  r.shape_model = QueryString(req, "shape_model", 64);
  r.use_stored_shape_model = QueryTrueFalse(req, "use_stored_shape_model", true);
  r.skip_nonfinite = QueryTrueFalse(req, "skip_nonfinite", false);
  r.match_iou = QueryNumber(req, "match_iou", r.match_iou, 1e-9, 1.0);
  return r;
}

Json FurnitureInstanceJson(const FurnitureInstanceView& v) {
  Json categories = Json::array();
  for (const CategoryShare& c : v.categories) categories.push_back({{"category", c.category}, {"probability", c.probability}});
  return {{"id", v.id}, {"perceived", v.perceived}, {"label", v.label}, {"label_probability", v.label_probability},
          {"categories", categories}, {"position_m", {v.position_m.x(), v.position_m.y()}},
          {"extent_m", {v.extent_m.x(), v.extent_m.y()}}, {"yaw_rad", v.yaw_rad}, {"min_z_m", v.min_z_m},
          {"height_m", v.height_m}, {"classifier", v.classifier}, {"evidence", v.evidence},
          {"observations", v.observations}, {"points", v.points}, {"updated_ns", v.updated_ns}};
}

}  // namespace

void RegisterSegmentationRoutes(Router& router, FurnitureSegmentationService& s) {
  RegisterJobDocumentWriters("furniture_segment",
      {[](const std::string& d, const std::string& what) { return ToJson(storage::DecodeSegmentationRequest(d, what)); },
       [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeSegmentationResult(d, what)); }});
  router.Add("POST", "/v1/maps/{map}/furniture:segment", Role::kWriter,
      "Segment the furniture (thesis 5.3.1) in the map's keyframes merged in the map frame or its OctoMap's occupied "
      "voxels (JSON {source: keyframes|octomap, keyframes, max_range_m, shape_model, use_stored_shape_model, "
      "match_iou, params}), or in a room cloud sent as the body (PCD / PLY, map frame; query shape_model, "
      "use_stored_shape_model, skip_nonfinite, match_iou). Each segment is classified by the named or else the "
      "newest stored shape model (verification mode) and becomes or updates a furniture instance (an operator's "
      "is never changed); 202 with the job",
      [&s](const httplib::Request& req, const PathParams& p) {
        const SegmentationRequest r = IsCloudBody(req) ? ParseCloudSegmentationRequest(req) : ParseSegmentationRequest(BodyObject(req));
        return JsonResponse(ToJson(s.Submit(p["map"], r)), 202);
      });
  router.Add("GET", "/v1/maps/{map}/furniture", Role::kReader,
      "The map's furniture instances: found by segmentation (p(f), footprint, height, yaw, evidence keyframes) or "
      "entered by an operator",
      [&s](const httplib::Request&, const PathParams& p) {
        Json items = Json::array();
        for (const FurnitureInstanceView& v : s.List(p["map"])) items.push_back(FurnitureInstanceJson(v));
        return JsonResponse(Json{{"furniture", items}});
      });
  router.Add("GET", "/v1/maps/{map}/furniture/{furniture}", Role::kReader, "One furniture instance",
      [&s](const httplib::Request&, const PathParams& p) {
        return JsonResponse(FurnitureInstanceJson(s.Get(p["map"], PathId(p, "furniture", "furniture"))));
      });
  router.Add("GET", "/v1/maps/{map}/furniture/{furniture}/cloud", Role::kReader,
      "The points (map frame, voxel-thinned) of the segment that last updated a perceived piece, as PCD or PLY "
      "(format as for keyframes)",
      [&s](const httplib::Request& req, const PathParams& p) {
        return BytesResponse(s.Cloud(p["map"], PathId(p, "furniture", "furniture"),
                                     octomap_json::ParseCloudFormat(Query(req, "format").value_or("pcd"))));
      });
}

}  // namespace anchordb::api
