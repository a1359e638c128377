// Routes of scene models and keyframes: parse, call SceneService, serialise (api/scene_json.h).
#include "api/scene_routes.h"

#include <cmath>

#include "api/exported_bytes_http.h"
#include "api/octomap_json.h"
#include "api/route_params.h"
#include "api/scene_json.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;
using namespace scene_json;

namespace {

std::int64_t SceneId(const PathParams& p) { return PathId(p, "scene", "scene"); }
std::int64_t KeyframeId(const PathParams& p) { return PathId(p, "keyframe", "keyframe"); }

bool IsPngType(const std::string& content_type) { return content_type.rfind("image/png", 0) == 0; }
bool IsRawType(const std::string& content_type) { return content_type.rfind("application/octet-stream", 0) == 0; }

// near=x,y,z&radius= (default 1 m), status=, limit= (1..1000, default 100).
SceneListFilter ParseListQuery(const httplib::Request& req) {
  SceneListFilter f;
  f.near_m = QueryPoint3(req, "near");
  if (f.near_m) {
    f.radius_m = OptionalQueryNumber(req, "radius").value_or(1.0);
    if (f.radius_m < 0) throw Error(ErrorCode::kUnprocessable, "radius must not be negative", "radius");
  }
  if (req.has_param("status")) {
    f.status = ValueOf(kSceneStatusNames, req.get_param_value("status"));
    if (!f.status) throw Error(ErrorCode::kInvalidArgument, "status must be observing, closed or superseded", "status");
  }
  const double limit = OptionalQueryNumber(req, "limit").value_or(100);
  if (limit < 1 || limit > 1000 || limit != std::floor(limit)) throw Error(ErrorCode::kUnprocessable, "limit must be an integer in [1, 1000]", "limit");
  f.limit = static_cast<int>(limit);
  return f;
}

// The body (PNG, raw) or the multipart parts depth and dynamic; stamp= and depth_scale= from the query. The views
// point into `req`.
FrameInput ParseFrame(const httplib::Request& req) {
  FrameInput in;
  in.stamp_ns = QueryTime(req, "stamp");
  in.depth_scale = OptionalQueryNumber(req, "depth_scale");
  in.wait_for_analysis = QueryBool(req, "wait_for_analysis");
  const std::string type = req.get_header_value("Content-Type");
  if (req.is_multipart_form_data()) {
    if (!req.has_file("depth")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'depth' is missing", "depth");
    const auto& depth = req.files.find("depth")->second;
    in.body = depth.content;
    in.png = !IsRawType(depth.content_type);
    if (req.has_file("dynamic")) in.dynamic_png = req.files.find("dynamic")->second.content;
  } else if (IsPngType(type) || IsRawType(type)) {
    in.body = req.body;
    in.png = IsPngType(type);
  } else {
    throw Error(ErrorCode::kUnsupportedMediaType,
                "frames are image/png, application/octet-stream or multipart/form-data; got '" + type + "'");
  }
  return in;
}

SceneLayerKind LayerKind(const PathParams& p) {
  const auto kind = ValueOf(kSceneLayerNames, p["layer"]);
  if (!kind) throw Error(ErrorCode::kNotFound, "scene layers are static, movable, dynamic and reliability", "layer");
  return *kind;
}

std::string LayerFormat(const httplib::Request& req) {
  const std::string format = req.has_param("format") ? req.get_param_value("format") : "png";
  if (format != "png" && format != "raw" && format != "json") {
    throw Error(ErrorCode::kInvalidArgument, "format must be png, raw or json", "format");
  }
  return format;
}

Response SummaryResponse(const SceneLayerSummary& s) {
  return {200, "application/json", LayerSummaryJson(s).dump(),
          {{"X-Image-Width", std::to_string(s.width)}, {"X-Image-Height", std::to_string(s.height)},
           {"X-Scene-Frames", std::to_string(s.frames)}}};
}

}  // namespace

void RegisterSceneRoutes(Router& router, SceneService& s) {
  router.Add("POST", "/v1/maps/{map}/scenes", Role::kWriter,
      "Open a scene model at a camera pose (camera intrinsics, pose, params beta/dynamic_mode/depth_scale)",
      [&s](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(SceneJson(s.Open(p["map"], ParseOpenScene(json::ParseObject(req.body))), false), 201);
      });
  router.Add("GET", "/v1/maps/{map}/scenes", Role::kReader, "Scene models of a map, newest first (near=x,y,z&radius=, status=, limit=)",
      [&s](const httplib::Request& req, const PathParams& p) { return JsonResponse(SceneListJson(s.List(p["map"], ParseListQuery(req)))); });
  router.Add("GET", "/v1/maps/{map}/scenes/{scene}", Role::kReader, "A scene model: camera, pose, status, frames, keyframes",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(SceneJson(s.Get(p["map"], SceneId(p)), true)); });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}/frames", Role::kWriter,
      "One depth frame: image/png (16-bit), application/octet-stream (raw uint16 LE), or multipart parts depth + dynamic; "
      "a keyframe it stores is analysed later unless wait_for_analysis=true",
      [&s](const httplib::Request& req, const PathParams& p) { return JsonResponse(FrameJson(s.AddFrame(p["map"], SceneId(p), ParseFrame(req)))); });
  router.Add("GET", "/v1/maps/{map}/scenes/{scene}/layers/{layer}", Role::kReader,
      "A scene layer (static, movable, dynamic, reliability) as png, raw or json; clean=true cleans the movable layer",
      [&s](const httplib::Request& req, const PathParams& p) {
        const bool clean = QueryBool(req, "clean");
        const std::string format = LayerFormat(req);
        const SceneLayerKind layer = LayerKind(p);
        if (format == "json") return SummaryResponse(s.LayerSummary(p["map"], SceneId(p), layer, clean));
        const auto encoding = format == "png" ? SceneLayerEncoding::kPng : SceneLayerEncoding::kRaw;
        return BytesResponse(s.Layer(p["map"], SceneId(p), layer, encoding, clean));
      });
  router.Add("GET", "/v1/maps/{map}/scenes/{scene}/cloud", Role::kReader,
      "A scene layer as a point cloud: layer=static|movable (movable pixels at the latest frame's depth), "
      "frame=map|camera, format=pcd|pcd_ascii|pcd_binary|pcd_binary_compressed|ply|ply_ascii|ply_binary",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string layer = QueryChoice(req, "layer", {"static", "movable"}).value_or("static");
        const std::string frame = QueryChoice(req, "frame", {"map", "camera"}).value_or("map");
        return BytesResponse(s.LayerCloud(p["map"], SceneId(p), *ValueOf(kSceneLayerNames, layer), frame == "map",
                                          octomap_json::ParseCloudFormat(Query(req, "format").value_or("pcd"))));
      });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}/keyframes", Role::kWriter, "Store a keyframe of the scene now (its change analysis is queued; wait_for_analysis=true waits for it)",
      [&s](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(KeyframeJson(s.Keyframe(p["map"], SceneId(p), QueryBool(req, "wait_for_analysis"))), 201);
      });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}:close", Role::kWriter, "End the observation: end keyframe (analysis queued; wait_for_analysis=true waits), state persisted",
      [&s](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(CloseJson(s.Close(p["map"], SceneId(p), QueryBool(req, "wait_for_analysis"))));
      });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}", Role::kReader, "A keyframe's metadata",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(KeyframeInfoJson(s.GetKeyframe(p["map"], KeyframeId(p)))); });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}/depth", Role::kReader, "A keyframe's raw depth as 16-bit PNG [mm]",
      [&s](const httplib::Request&, const PathParams& p) { return BytesResponse(s.KeyframeImage(p["map"], KeyframeId(p), KeyframeImageKind::kDepth)); });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}/background", Role::kReader,
      "A keyframe's static background as 16-bit PNG [mm]", [&s](const httplib::Request&, const PathParams& p) {
        return BytesResponse(s.KeyframeImage(p["map"], KeyframeId(p), KeyframeImageKind::kBackground));
      });
}

}  // namespace anchordb::api
