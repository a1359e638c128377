// The octomap routes of /v1 (SPEC 4.9): the per-map 3D occupancy tree — configure, import / export .bt / .ot,
// insert clouds by ray casting, point / ray / box queries, operator box clears, occupied voxels as a cloud.
#include "api/octomap_routes.h"

#include "api/exported_bytes_http.h"
#include "api/http_api.h"
#include "api/octomap_json.h"
#include "api/route_params.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;
using octomap_json::ToJson;

namespace {

bool IsJson(const httplib::Request& req) {
  return req.get_header_value("Content-Type").rfind("application/json", 0) == 0;
}

TreeFileFormat ImportFormat(const httplib::Request& req) {
  if (const auto f = Query(req, "format")) return octomap_json::ParseTreeFormat(*f);
  if (req.body.rfind("# Octomap OcTree binary file", 0) == 0) return TreeFileFormat::kBt;
  if (req.body.rfind("# Octomap OcTree file", 0) == 0) return TreeFileFormat::kOt;
  throw Error(ErrorCode::kInvalidArgument, "the body is neither an OctoMap .bt nor .ot file (or give format=bt|ot)",
              "body");
}

}  // namespace

void RegisterOctomapRoutes(Router& router, OctomapService& s) {
  router.Add("PUT", "/v1/maps/{map}/octomap", Role::kWriter,
      "Create or configure the map's occupancy tree (JSON resolution_m, sensor model, max_range_m) or import an "
      "OctoMap file (body .bt or .ot; format=bt|ot, else by its header)",
      [&s](const httplib::Request& req, const PathParams& p) {
        if (IsJson(req)) return JsonResponse(ToJson(s.Configure(p["map"], octomap_json::ParseConfig(BodyObject(req)))));
        if (req.body.empty()) throw Error(ErrorCode::kInvalidArgument, "the body is empty", "body");
        return JsonResponse(ToJson(s.Import(p["map"], ImportFormat(req), req.body)));
      });
  router.Add("GET", "/v1/maps/{map}/octomap", Role::kReader,
      "The map's occupancy tree: format=json (metadata), bt, ot, or its occupied voxel centres as pcd, pcd_ascii, "
      "pcd_binary, pcd_binary_compressed, ply, ply_ascii, ply_binary",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string format = Query(req, "format").value_or("json");
        if (format == "json") return JsonResponse(ToJson(s.Get(p["map"])));
        if (format == "bt" || format == "ot") return BytesResponse(s.Export(p["map"], octomap_json::ParseTreeFormat(format)));
        return BytesResponse(s.ExportOccupiedCloud(p["map"], octomap_json::ParseCloudFormat(format)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap/points", Role::kWriter,
      "Insert a point cloud (PCD ascii / binary / binary_compressed or PLY body, map frame) by ray casting from "
      "origin=x,y,z (else the cloud's viewpoint); max_range_m, skip_nonfinite=true, stamp",
      [&s](const httplib::Request& req, const PathParams& p) {
        InsertCloudRequest r;
        r.map = p["map"];
        r.body = req.body;
        r.origin_map = QueryPoint3(req, "origin");
        r.max_range_m = OptionalQueryNumber(req, "max_range_m");
        r.skip_nonfinite = QueryTrueFalse(req, "skip_nonfinite", false);
        r.stamp_ns = QueryTime(req, "stamp");
        return JsonResponse(ToJson(s.InsertCloud(r)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap/query", Role::kReader,
      "Occupancy state (occupied / free / unknown), probability and last update at each of points [[x,y,z],...]",
      [&s](const httplib::Request& req, const PathParams& p) {
        const auto points = octomap_json::ParsePoints(BodyObject(req), s.settings().max_query_points);
        return JsonResponse(ToJson(s.Query(p["map"], points)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap/ray", Role::kReader,
      "Cast a ray {origin, direction, max_range_m, ignore_unknown}: the first occupied voxel, or where unknown space "
      "or the range stopped it",
      [&s](const httplib::Request& req, const PathParams& p) {
        RayRequest r = octomap_json::ParseRay(BodyObject(req));
        r.map = p["map"];
        return JsonResponse(ToJson(s.CastRay(r)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap/voxels", Role::kReader,
      "Occupied voxels whose centre lies in the box {min, max} (at most limit, and octomap_max_voxels)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const Json body = BodyObject(req);
        const engine::Box3 box = octomap_json::ParseBox(body, {"limit"});
        std::optional<std::size_t> limit;
        if (body.contains("limit")) {
          const std::int64_t l = json::IntegerOr(body, "limit", 0);
          if (l < 1) throw Error(ErrorCode::kUnprocessable, "limit must be at least 1", "limit");
          limit = static_cast<std::size_t>(l);
        }
        return JsonResponse(ToJson(s.OccupiedVoxels(p["map"], box, limit)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap:project", Role::kWriter,
      "Project height bands of the tree into 2D occupancy layers (map_server-exportable; unknown stays unknown): "
      "{layer, min_z_m, max_z_m} or {bands:[...]}, on the grid of like (else the map's occupancy layer, else the tree's box)",
      [&s](const httplib::Request& req, const PathParams& p) {
        ProjectRequest r = octomap_json::ParseProject(BodyObject(req));
        r.map = p["map"];
        return JsonResponse(ToJson(s.Project(r)));
      });
  router.Add("POST", "/v1/maps/{map}/octomap:clear", Role::kAdmin,
      "Operator clear of a box {min, max}: its known voxels become free, unknown stays unknown (audited)",
      [&s](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(s.ClearBox(p["map"], octomap_json::ParseBox(BodyObject(req)))));
      });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}/cloud", Role::kReader,
      "A keyframe as a point cloud: format=pcd|pcd_ascii|pcd_binary|pcd_binary_compressed|ply|ply_ascii|ply_binary, "
      "frame=map|camera, image=depth|background (the static background when it was stored)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string frame = QueryChoice(req, "frame", {"map", "camera"}).value_or("map");
        const std::string image = QueryChoice(req, "image", {"depth", "background"}).value_or("depth");
        return BytesResponse(s.KeyframeCloud(p["map"], PathId(p, "keyframe", "keyframe"), image == "background", frame == "map",
                                     octomap_json::ParseCloudFormat(Query(req, "format").value_or("pcd"))));
      });
  router.Add("GET", "/v1/maps/{map}/events/{event}/cloud", Role::kReader,
      "The stored points (up to 256, map frame) of a change event's segment as PCD or PLY (format as for keyframes)",
      [&s](const httplib::Request& req, const PathParams& p) {
        return BytesResponse(s.EventSegmentCloud(p["map"], PathId(p, "event", "event"),
                                         octomap_json::ParseCloudFormat(Query(req, "format").value_or("pcd"))));
      });
  router.Add("POST", "/v1/maps/{map}/octomap:decay", Role::kAdmin,
      "Forgetting for the tree: voxels not confirmed for max_age_s (before now, default the wall clock) go back to "
      "unknown; reports how many leaves went (audited)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const Json body = BodyObject(req);
        json::RejectUnknownKeys(body, {"max_age_s", "now"});
        const double age_s = json::RequireFiniteNumber(body, "max_age_s");
        if (age_s < 0 || age_s > 100 * 365.25 * 86400) {
          throw Error(ErrorCode::kUnprocessable, "max_age_s must be in [0, 100 years] seconds", "max_age_s");
        }
        const std::optional<std::int64_t> now = body.contains("now") ? std::optional<std::int64_t>(json::AsStampNs(body.at("now"), "now"))
                                                                    : std::nullopt;
        const DecayResult r = s.Decay(p["map"], age_s, now);
        return JsonResponse({{"voxels_forgotten", r.leaves_forgotten}, {"cutoff_ns", r.cutoff_ns},
                             {"octomap", ToJson(r.octomap)}});
      });
}

}  // namespace anchordb::api
