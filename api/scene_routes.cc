// Routes of scene models and keyframes: parse, call SceneService, serialise.
#include "api/scene_routes.h"
#include <cmath>

#include "api/http_api.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
namespace {

Response JsonResponse(const Json& j, int status = 200) { return {status, "application/json", j.dump(), {}}; }

std::int64_t IdParam(const PathParams& p, const std::string& name) {
  const std::string& text = p[name];
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
    throw Error(ErrorCode::kNotFound, name + " '" + text + "' does not exist (ids are integers)", name);
  }
  return std::stoll(text);
}

std::optional<double> OptionalQueryNumber(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return std::nullopt;
  const std::string text = req.get_param_value(name);
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be a finite number", name);
  }
  return v;
}

std::optional<std::int64_t> QueryStamp(const httplib::Request& req) {
  if (!req.has_param("stamp")) return std::nullopt;
  const std::string text = req.get_param_value("stamp");
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos && text.size() <= 19) return std::stoll(text);
  return json::AsStampNs(Json(text), "stamp");
}

bool QueryBool(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return false;
  const std::string v = req.get_param_value(name);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  throw Error(ErrorCode::kInvalidArgument, name + " must be true or false", name);
}

bool IsPngType(const std::string& content_type) { return content_type.rfind("image/png", 0) == 0; }
bool IsRawType(const std::string& content_type) { return content_type.rfind("application/octet-stream", 0) == 0; }

}  // namespace

void RegisterSceneRoutes(Router& router, SceneService& s) {
  router.Add("POST", "/v1/maps/{map}/scenes", Role::kWriter,
      "Open a scene model at a camera pose (camera intrinsics, pose, params beta/dynamic_mode/depth_scale)",
      [&s](const httplib::Request& req, const PathParams& p) { return JsonResponse(s.Open(p["map"], json::ParseObject(req.body)), 201); });
  router.Add("GET", "/v1/maps/{map}/scenes", Role::kReader, "Scene models of a map, newest first (near=x,y,z&radius=, status=, limit=)",
      [&s](const httplib::Request& req, const PathParams& p) {
        storage::SceneFilter f;
        if (req.has_param("near")) {
          double v[3];
          char tail = 0;
          if (std::sscanf(req.get_param_value("near").c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3 ||
              !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
            throw Error(ErrorCode::kInvalidArgument, "near must be x,y,z in metres", "near");
          }
          f.near_m = Eigen::Vector3d(v[0], v[1], v[2]);
          f.radius_m = OptionalQueryNumber(req, "radius").value_or(1.0);
          if (f.radius_m < 0) throw Error(ErrorCode::kUnprocessable, "radius must not be negative", "radius");
        }
        if (req.has_param("status")) {
          const std::string status = req.get_param_value("status");
          if (status != "observing" && status != "closed" && status != "superseded") {
            throw Error(ErrorCode::kInvalidArgument, "status must be observing, closed or superseded", "status");
          }
          f.status = status;
        }
        const double limit = OptionalQueryNumber(req, "limit").value_or(100);
        if (limit < 1 || limit > 1000 || limit != std::floor(limit)) throw Error(ErrorCode::kUnprocessable, "limit must be an integer in [1, 1000]", "limit");
        f.limit = static_cast<int>(limit);
        return JsonResponse(s.List(p["map"], f));
      });
  router.Add("GET", "/v1/maps/{map}/scenes/{scene}", Role::kReader, "A scene model: camera, pose, status, frames, keyframes",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(s.Get(p["map"], IdParam(p, "scene"))); });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}/frames", Role::kWriter,
      "One depth frame: image/png (16-bit), application/octet-stream (raw uint16 LE), or multipart parts depth + dynamic",
      [&s](const httplib::Request& req, const PathParams& p) {
        FrameInput in;
        in.stamp_ns = QueryStamp(req);
        in.depth_scale = OptionalQueryNumber(req, "depth_scale");
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
        return JsonResponse(s.AddFrame(p["map"], IdParam(p, "scene"), in));
      });
  router.Add("GET", "/v1/maps/{map}/scenes/{scene}/layers/{layer}", Role::kReader,
      "A scene layer (static, movable, dynamic, reliability) as png, raw or json; clean=true cleans the movable layer",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string format = req.has_param("format") ? req.get_param_value("format") : "png";
        ExportedLayer e = s.Layer(p["map"], IdParam(p, "scene"), p["layer"], format, QueryBool(req, "clean"));
        return Response{200, e.content_type, std::move(e.body), e.headers};
      });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}/keyframes", Role::kWriter, "Store a keyframe of the scene now",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(s.Keyframe(p["map"], IdParam(p, "scene")), 201); });
  router.Add("POST", "/v1/maps/{map}/scenes/{scene}:close", Role::kWriter, "End the observation: end keyframe, state persisted",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(s.Close(p["map"], IdParam(p, "scene"))); });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}", Role::kReader, "A keyframe's metadata",
      [&s](const httplib::Request&, const PathParams& p) { return JsonResponse(s.GetKeyframe(p["map"], IdParam(p, "keyframe"))); });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}/depth", Role::kReader, "A keyframe's raw depth as 16-bit PNG [mm]",
      [&s](const httplib::Request&, const PathParams& p) {
        ExportedLayer e = s.KeyframeImage(p["map"], IdParam(p, "keyframe"), "depth");
        return Response{200, e.content_type, std::move(e.body), e.headers};
      });
  router.Add("GET", "/v1/maps/{map}/keyframes/{keyframe}/background", Role::kReader,
      "A keyframe's static background as 16-bit PNG [mm]", [&s](const httplib::Request&, const PathParams& p) {
        ExportedLayer e = s.KeyframeImage(p["map"], IdParam(p, "keyframe"), "background");
        return Response{200, e.content_type, std::move(e.body), e.headers};
      });
}

}  // namespace anchordb::api
