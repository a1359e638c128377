// Routes of furniture graphs and grounding (thesis 5.3): parse (api/furniture_json.h), call FurnitureService,
// serialise.
#include "api/furniture_routes.h"

#include "api/furniture_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

std::int64_t GraphId(const PathParams& p) { return PathId(p, "graph", "furniture graph"); }

}  // namespace

void RegisterFurnitureRoutes(Router& router, FurnitureService& f) {
  router.Add("POST", "/v1/maps/{map}/furniture-graphs", Role::kWriter,
      "Build a furniture graph from furniture seen from a viewpoint (viewpoint, furniture with category "
      "probabilities, params model/n_best/sigma/edge_max_gap_m/relation_sharpness/adaptation/frame_prior/ambiguity_margin/category_floor/orientation_prior/occupancy_layer)",
      [&f](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(f.Create(p["map"], ParseCreateGraph(json::ParseObject(req.body)))), 201);
      });
  router.Add("GET", "/v1/maps/{map}/furniture-graphs", Role::kReader, "Furniture graphs of a map, newest first (before=, limit=)",
      [&f](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(f.List(p["map"], QueryInteger(req, "before", 0, 0, 9'000'000'000'000'000'000),
                                          static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000)))));
      });
  router.Add("GET", "/v1/maps/{map}/furniture-graphs/{graph}", Role::kReader,
      "The best furniture graph: vertices with p(f) and p(o), edges with p(r), and the grounded descriptions",
      [&f](const httplib::Request&, const PathParams& p) { return JsonResponse(ToJson(f.Get(p["map"], GraphId(p)))); });
  router.Add("POST", "/v1/maps/{map}/furniture-graphs/{graph}/descriptions", Role::kWriter,
      "Ground one spatial description: {located, relation, reference} or {text} (\"the table is in front of the shelf\")",
      [&f](const httplib::Request& req, const PathParams& p) {
        const DescriptionRequest d = ParseDescription(json::ParseObject(req.body), f.settings().max_text_length);
        return JsonResponse(ToJson(f.Describe(p["map"], GraphId(p), d)), 201);
      });
  router.Add("GET", "/v1/maps/{map}/furniture-graphs/{graph}/hypotheses", Role::kReader,
      "The live n-best hypotheses, best first (limit=, default 20)", [&f](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(f.Hypotheses(p["map"], GraphId(p), static_cast<int>(QueryInteger(req, "limit", 20, 1, 100000)))));
      });
  router.Add("POST", "/v1/maps/{map}/furniture-graphs/{graph}:reset", Role::kWriter,
      "Forget the descriptions: back to the graph as seen", [&f](const httplib::Request&, const PathParams& p) {
        return JsonResponse(ToJson(f.Reset(p["map"], GraphId(p))));
      });
  router.Add("POST", "/v1/maps/{map}/furniture-graphs/{graph}:resolve", Role::kWriter,
      "Settle an ambiguous description by naming its pieces {seq?, located, reference}: its held category update applies",
      [&f](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(f.Resolve(p["map"], GraphId(p), ParseResolve(json::ParseObject(req.body)))));
      });
  router.Add("POST", "/v1/maps/{map}/furniture-graphs/{graph}:describe", Role::kReader,
      "Speech production: how this listener most likely names two pieces and their relation {located, reference}",
      [&f](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(ToJson(f.Produce(p["map"], GraphId(p), ParseProduce(json::ParseObject(req.body)))));
      });
}

}  // namespace anchordb::api
