// The grid routes of /v1 (maps, layers, agents, attention, viewpoints) and their thin handlers: parse the request
// (api/grid_json.h, api/route_params.h), call one GridService function, serialise its result.
#include "api/grid_routes.h"

#include "api/exported_bytes_http.h"
#include "api/grid_json.h"
#include "api/http_api.h"
#include "api/route_params.h"
#include "schema/error.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;
using grid_json::ToJson;

namespace {

Json Body(const httplib::Request& req) { return json::ParseObject(req.body); }

void RegisterMapRoutes(Router& router, GridService& s) {
  router.Add("POST", "/v1/maps", Role::kWriter, "Create a map", [&s](const httplib::Request& req, const PathParams&) {
    return JsonResponse(ToJson(s.CreateMap(grid_json::ParseCreateMap(Body(req)))), 201);
  });
  router.Add("GET", "/v1/maps", Role::kReader, "List maps (paginated by cursor)", [&s](const httplib::Request& req, const PathParams&) {
    const int limit = QueryWholeNumber(req, "limit", 100, 1, s.limits().max_list_limit);
    return JsonResponse(ToJson(s.ListMaps({Query(req, "cursor").value_or(""), limit})));
  });
  router.Add("GET", "/v1/maps/{map}", Role::kReader, "A map with its layers", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(ToJson(s.GetMap(p["map"])));
  });
  router.Add("DELETE", "/v1/maps/{map}", Role::kAdmin, "Delete a map and everything in it", [&s](const httplib::Request&, const PathParams& p) {
    s.DeleteMap(p["map"]);
    return JsonResponse({{"deleted", p["map"]}});
  });
}

void RegisterLayerRoutes(Router& router, GridService& s) {
  router.Add("GET", "/v1/maps/{map}/layers", Role::kReader, "List a map's layers", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(ToJson(s.ListLayers(p["map"])));
  });
  router.Add("PUT", "/v1/maps/{map}/layers/{layer}", Role::kWriter,
      "Import an occupancy layer (multipart yaml + image) or create a probability, fused or label layer (JSON)",
      [&s](const httplib::Request& req, const PathParams& p) {
        if (req.is_multipart_form_data()) {
          if (!req.has_file("yaml")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'yaml' is missing", "yaml");
          if (!req.has_file("image")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'image' is missing", "image");
          return JsonResponse(ToJson(s.ImportOccupancyLayer({p["map"], p["layer"], req.get_file_value("yaml").content,
                                                             req.get_file_value("image").content})), 201);
        }
        const LayerSpec spec = grid_json::ParseLayerSpec(Body(req), p["layer"]);
        return JsonResponse(ToJson(s.CreateLayer({p["map"], p["layer"], spec})), 201);
      });
  router.Add("GET", "/v1/maps/{map}/layers/{layer}", Role::kReader,
      "Read a layer: format=json (metadata, statistics=true adds statistics), png, pgm, yaml or raw",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string format = Query(req, "format").value_or("json");
        if (format == "json") {
          return JsonResponse(ToJson(s.GetLayer(p["map"], p["layer"], QueryTrueFalse(req, "statistics", false))));
        }
        return BytesResponse(s.ExportLayer(p["map"], p["layer"], grid_json::ParseLayerFormat(format)));
      });
  router.Add("DELETE", "/v1/maps/{map}/layers/{layer}", Role::kAdmin, "Delete a layer nothing depends on",
      [&s](const httplib::Request&, const PathParams& p) {
        s.DeleteLayer(p["map"], p["layer"]);
        return JsonResponse({{"deleted", p["layer"]}});
      });
  router.Add("POST", "/v1/maps/{map}/layers/{layer}/observations", Role::kWriter,
      "Observation update of a probability layer (pose, fov_rad, range_m, stimulus polygons)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const engine::Observation observation = grid_json::ParseObservation(Body(req), s.limits());
        return JsonResponse(ToJson(s.Observe({p["map"], p["layer"], observation})));
      });
  router.Add("POST", "/v1/maps/{map}/layers/{layer}/labels", Role::kWriter, "Paint a label into a label layer over polygons",
      [&s](const httplib::Request& req, const PathParams& p) {
        PaintLabelRequest request = grid_json::ParsePaintLabel(Body(req), s.limits());
        request.map = p["map"];
        request.layer = p["layer"];
        return JsonResponse(ToJson(s.PaintLabel(request)));
      });
  router.Add("GET", "/v1/maps/{map}/layers/{layer}/regions", Role::kReader,
      "Regions above a threshold (region growing): polygons, area, centroid",
      [&s](const httplib::Request& req, const PathParams& p) {
        const double threshold = QueryNumber(req, "threshold", 0.5, 0.0, 1.0);
        const double min_area = QueryNumber(req, "min_area_m2", 0.0, 0.0, 1e9);
        return JsonResponse(ToJson(s.Regions({p["map"], p["layer"], threshold, min_area})));
      });
}

void RegisterAgentRoutes(Router& router, GridService& s) {
  router.Add("PUT", "/v1/maps/{map}/agents/{agent}", Role::kWriter, "Create or update a tracked person",
      [&s](const httplib::Request& req, const PathParams& p) {
        PutAgentRequest request = grid_json::ParsePutAgent(Body(req));
        request.map = p["map"];
        request.agent.id = p["agent"];
        return JsonResponse(json::ToJson(s.PutAgent(request)));
      });
  router.Add("GET", "/v1/maps/{map}/agents/{agent}", Role::kReader, "A tracked person", [&s](const httplib::Request&, const PathParams& p) {
    return JsonResponse(json::ToJson(s.GetAgent(p["map"], p["agent"])));
  });
  router.Add("GET", "/v1/maps/{map}/agents", Role::kReader, "Tracked persons, optionally within bbox=min_x,min_y,max_x,max_y",
      [&s](const httplib::Request& req, const PathParams& p) { return JsonResponse(ToJson(s.ListAgents(p["map"], QueryBbox(req)))); });
  router.Add("GET", "/v1/maps/{map}/attention", Role::kReader,
      "Whether a person stands next to a surface region and faces it (agent=, layer=, threshold=)",
      [&s](const httplib::Request& req, const PathParams& p) {
        const std::string agent = RequireQueryId(req, "agent");
        const std::string layer = RequireQueryId(req, "layer");
        return JsonResponse(ToJson(s.Attention({p["map"], agent, layer, QueryNumber(req, "threshold", 0.5, 0.0, 1.0)})));
      });
  router.Add("POST", "/v1/maps/{map}/viewpoints", Role::kReader, "Ranked observation viewpoints around the attended surface",
      [&s](const httplib::Request& req, const PathParams& p) {
        ViewpointsRequest request = grid_json::ParseViewpoints(Body(req));
        request.map = p["map"];
        return JsonResponse(ToJson(s.Viewpoints(request)));
      });
}

}  // namespace

void RegisterGridRoutes(Router& router, GridService& service) {
  RegisterMapRoutes(router, service);
  RegisterLayerRoutes(router, service);
  RegisterAgentRoutes(router, service);
}

}  // namespace anchordb::api
