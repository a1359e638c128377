// The route table of /v1 and its thin handlers: parse the request, call one GridService function, serialise.
#include "api/grid_routes.h"
#include <cmath>

#include "api/http_api.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
namespace {

Response JsonResponse(const Json& j, int status = 200) { return {status, "application/json", j.dump(), {}}; }

Json Body(const httplib::Request& req) { return json::ParseObject(req.body); }

std::optional<std::string> Query(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

double QueryNumber(const httplib::Request& req, const std::string& name, double fallback, double lo, double hi) {
  const auto text = Query(req, name);
  if (!text) return fallback;
  char* end = nullptr;
  const double v = std::strtod(text->c_str(), &end);
  if (text->empty() || end != text->c_str() + text->size() || !std::isfinite(v)) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be a finite number", name);
  }
  if (v < lo || v > hi) {
    throw Error(ErrorCode::kUnprocessable, name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", name);
  }
  return v;
}

int QueryInt(const httplib::Request& req, const std::string& name, int fallback, int lo, int hi) {
  const double v = QueryNumber(req, name, fallback, lo, hi);
  if (v != std::floor(v)) throw Error(ErrorCode::kInvalidArgument, name + " must be an integer", name);
  return static_cast<int>(v);
}

std::string RequireQueryId(const httplib::Request& req, const std::string& name) {
  const auto v = Query(req, name);
  if (!v) throw Error(ErrorCode::kInvalidArgument, "query parameter '" + name + "' is required", name);
  json::CheckId(*v, name);
  return *v;
}

std::optional<storage::Bbox> QueryBbox(const httplib::Request& req) {
  const auto text = Query(req, "bbox");
  if (!text) return std::nullopt;
  double v[4];
  char tail = 0;
  if (std::sscanf(text->c_str(), "%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &tail) != 4 ||
      !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) {
    throw Error(ErrorCode::kInvalidArgument, "bbox must be min_x,min_y,max_x,max_y in metres", "bbox");
  }
  if (v[0] > v[2] || v[1] > v[3]) throw Error(ErrorCode::kUnprocessable, "bbox minimum exceeds its maximum", "bbox");
  return storage::Bbox{v[0], v[1], v[2], v[3]};
}

engine::Observation ParseObservation(const Json& body, const ServiceLimits& limits) {
  json::RejectUnknownKeys(body, {"pose", "fov_rad", "range_m", "stimulus", "stamp"});
  engine::Observation obs;
  const Pose3 pose = json::AsPose3(json::Require(body, "pose"), "pose");
  obs.sensor_position_m = pose.position_m.head<2>();
  obs.heading_rad = pose.YawRad();
  obs.fov_rad = json::RequireFiniteNumber(body, "fov_rad");
  obs.range_m = json::RequireFiniteNumber(body, "range_m");
  if (obs.fov_rad <= 0.0 || obs.fov_rad > 2.0 * M_PI + 1e-9) {
    throw Error(ErrorCode::kUnprocessable, "fov_rad must be in (0, 2*pi]", "fov_rad");
  }
  if (obs.range_m <= 0.0 || obs.range_m > 100.0) throw Error(ErrorCode::kUnprocessable, "range_m must be in (0, 100]", "range_m");
  if (body.contains("stamp")) json::AsStampNs(body["stamp"], "stamp");
  obs.stimulus_M = json::AsPolygons(json::Require(body, "stimulus"), "stimulus", limits.max_polygons, limits.max_polygon_vertices);
  return obs;
}

}  // namespace

void RegisterGridRoutes(Router& router, GridService& s) {
  const ServiceLimits& limits = s.limits();

  // ---- maps
  router.Add("POST", "/v1/maps", Role::kWriter, "Create a map", [&s](const httplib::Request& req, const PathParams&) {
    const Json body = Body(req);
    json::RejectUnknownKeys(body, {"id", "name"});
    const std::string id = json::RequireId(body, "id");
    const std::string name = json::OptionalString(body, "name", 256).value_or(id);
    return JsonResponse(s.CreateMap(id, name), 201);
  });
  router.Add("GET", "/v1/maps", Role::kReader, "List maps (paginated by cursor)", [&s, &limits](const httplib::Request& req, const PathParams&) {
    const int limit = QueryInt(req, "limit", 100, 1, limits.max_list_limit);
    const std::string cursor = Query(req, "cursor").value_or("");
    return JsonResponse(s.ListMaps(cursor, limit));
  });
  router.Add("GET", "/v1/maps/{map}", Role::kReader, "A map with its layers", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(s.GetMap(p["map"]));
  });
  router.Add("DELETE", "/v1/maps/{map}", Role::kAdmin, "Delete a map and everything in it", [&s](const httplib::Request&, const PathParams& p) {
    s.DeleteMap(p["map"]);
    return JsonResponse({{"deleted", p["map"]}});
  });

  // ---- layers
  router.Add("GET", "/v1/maps/{map}/layers", Role::kReader, "List a map's layers", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(s.ListLayers(p["map"]));
  });
  router.Add("PUT", "/v1/maps/{map}/layers/{layer}", Role::kWriter,
      "Import an occupancy layer (multipart yaml + image) or create a probability, fused or label layer (JSON)",
      [&s](const httplib::Request& req, const PathParams& p) {
        if (req.is_multipart_form_data()) {
          if (!req.has_file("yaml")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'yaml' is missing", "yaml");
          if (!req.has_file("image")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'image' is missing", "image");
          return JsonResponse(s.ImportOccupancyLayer(p["map"], p["layer"], req.get_file_value("yaml").content,
                                                     req.get_file_value("image").content), 201);
        }
        return JsonResponse(s.CreateLayer(p["map"], p["layer"], Body(req)), 201);
      });
  router.Add("GET", "/v1/maps/{map}/layers/{layer}", Role::kReader,
      "Read a layer: format=json (metadata, statistics=true adds statistics), png, pgm, yaml or raw",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string format = Query(req, "format").value_or("json");
        if (format == "json") {
          const std::string stats = Query(req, "statistics").value_or("false");
          if (stats != "true" && stats != "false") throw Error(ErrorCode::kInvalidArgument, "statistics must be true or false", "statistics");
          return JsonResponse(s.LayerInfo(p["map"], p["layer"], stats == "true"));
        }
        ExportedLayer e = s.ExportLayer(p["map"], p["layer"], format);
        return Response{200, e.content_type, std::move(e.body), e.headers};
      });
  router.Add("DELETE", "/v1/maps/{map}/layers/{layer}", Role::kAdmin, "Delete a layer nothing depends on",
      [&s](const httplib::Request&, const PathParams& p) {
        s.DeleteLayer(p["map"], p["layer"]);
        return JsonResponse({{"deleted", p["layer"]}});
      });
  router.Add("POST", "/v1/maps/{map}/layers/{layer}/observations", Role::kWriter,
      "Observation update of a probability layer (pose, fov_rad, range_m, stimulus polygons)",
      [&s, &limits](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(s.Observe(p["map"], p["layer"], ParseObservation(Body(req), limits)));
      });
  router.Add("POST", "/v1/maps/{map}/layers/{layer}/labels", Role::kWriter, "Paint a label into a label layer over polygons",
      [&s, &limits](const httplib::Request& req, const PathParams& p) {
        const Json body = Body(req);
        json::RejectUnknownKeys(body, {"label", "polygons"});
        const std::string label = json::RequireString(body, "label", 128);
        if (label.empty()) throw Error(ErrorCode::kInvalidArgument, "label must not be empty", "label");
        const auto polygons = json::AsPolygons(json::Require(body, "polygons"), "polygons", limits.max_polygons,
                                               limits.max_polygon_vertices);
        return JsonResponse(s.PaintLabel(p["map"], p["layer"], label, polygons));
      });
  router.Add("GET", "/v1/maps/{map}/layers/{layer}/regions", Role::kReader,
      "Regions above a threshold (region growing): polygons, area, centroid",
      [&s](const httplib::Request& req, const PathParams& p) {
        const double threshold = QueryNumber(req, "threshold", 0.5, 0.0, 1.0);
        const double min_area = QueryNumber(req, "min_area_m2", 0.0, 0.0, 1e9);
        return JsonResponse(s.Regions(p["map"], p["layer"], threshold, min_area));
      });

  // ---- agents, attention, viewpoints
  router.Add("PUT", "/v1/maps/{map}/agents/{agent}", Role::kWriter, "Create or update a tracked person",
      [&s](const httplib::Request& req, const PathParams& p) {
        const Json body = Body(req);
        json::RejectUnknownKeys(body, {"position", "heading_rad", "velocity", "stamp"});
        Agent a;
        a.id = p["agent"];
        a.position_m = json::AsVector2(json::Require(body, "position"), "position");
        a.heading_rad = std::remainder(json::RequireFiniteNumber(body, "heading_rad"), 2.0 * M_PI);
        if (body.contains("velocity")) a.velocity_mps = json::AsVector2(body["velocity"], "velocity");
        a.stamp_ns = body.contains("stamp") ? json::AsStampNs(body["stamp"], "stamp")
                                            : std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                  std::chrono::system_clock::now().time_since_epoch()).count();
        return JsonResponse(s.PutAgent(p["map"], a));
      });
  router.Add("GET", "/v1/maps/{map}/agents/{agent}", Role::kReader, "A tracked person", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(s.GetAgent(p["map"], p["agent"]));
  });
  router.Add("GET", "/v1/maps/{map}/agents", Role::kReader, "Tracked persons, optionally within bbox=min_x,min_y,max_x,max_y",
      [&s](const httplib::Request& req, const PathParams& p) { return JsonResponse(s.ListAgents(p["map"], QueryBbox(req))); });
  router.Add("GET", "/v1/maps/{map}/attention", Role::kReader,
      "Whether a person stands next to a surface region and faces it (agent=, layer=, threshold=)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string agent = RequireQueryId(req, "agent");
        const std::string layer = RequireQueryId(req, "layer");
        return JsonResponse(s.Attention(p["map"], agent, layer, QueryNumber(req, "threshold", 0.5, 0.0, 1.0)));
      });
  router.Add("POST", "/v1/maps/{map}/viewpoints", Role::kReader, "Ranked observation viewpoints around the attended surface",
      [&s](const httplib::Request& req, const PathParams& p) {
        const Json body = Body(req);
        json::RejectUnknownKeys(body, {"robot", "agent", "layer", "threshold", "region", "max"});
        const Eigen::Vector2d robot = json::AsVector2(json::Require(body, "robot"), "robot");
        const std::string agent = json::RequireId(body, "agent");
        const std::string layer = json::RequireId(body, "layer");
        const double threshold = json::FiniteNumberOr(body, "threshold", 0.5);
        if (threshold < 0.0 || threshold > 1.0) throw Error(ErrorCode::kUnprocessable, "threshold must be in [0, 1]", "threshold");
        std::optional<int> region;
        if (body.contains("region")) region = static_cast<int>(json::IntegerOr(body, "region", 0));
        const auto max = json::IntegerOr(body, "max", 10);
        if (max < 1 || max > 100) throw Error(ErrorCode::kUnprocessable, "max must be in [1, 100]", "max");
        return JsonResponse(s.Viewpoints(p["map"], robot, agent, layer, threshold, region, static_cast<int>(max)));
      });
}

}  // namespace anchordb::api
