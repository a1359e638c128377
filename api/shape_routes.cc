// Routes of shape models: parse (api/shape_json.h), call one ShapeService function, serialise.
#include "api/shape_routes.h"

#include "api/shape_documents_json.h"
#include "api/job_json.h"
#include "api/route_params.h"
#include "api/shape_json.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

void RegisterShapeRoutes(Router& router, ShapeService& s) {
  RegisterShapeJobDocumentWriters();
  using Req = const httplib::Request&;
  router.Add("POST", "/v1/shape-models", Role::kWriter,
      "Train a 3D shape model (ISM with ray-based Hough voting) as a job: multipart part spec (JSON {name, params?, "
      "mesh_views?, categories?, samples: [{part, category, kind: cloud|mesh}]}) and one part per sample (PCD / PLY "
      "cloud or OBJ mesh, metres); 202 with the job",
      [&s](Req req, const PathParams&) {
        if (!req.is_multipart_form_data()) {
          throw Error(ErrorCode::kUnsupportedMediaType, "POST /v1/shape-models takes multipart/form-data", "body");
        }
        if (!req.has_file("spec")) throw Error(ErrorCode::kInvalidArgument, "multipart part 'spec' is missing", "spec");
        const Json spec = json::ParseObject(req.get_file_value("spec").content);
        const auto part = [&req](const std::string& name) -> const std::string* {
          const auto it = req.files.find(name);
          return it == req.files.end() ? nullptr : &it->second.content;
        };
        return JsonResponse(ToJson(s.SubmitTraining(ParseTrainShapeModelRequest(spec, part))), 202);
      });
  router.Add("GET", "/v1/shape-models", Role::kReader, "Trained shape models with their training reports",
      [&s](Req, const PathParams&) {
        Json list = Json::array();
        for (const auto& v : s.List()) list.push_back(ToJson(v));
        return JsonResponse({{"shape_models", list}});
      });
  router.Add("GET", "/v1/shape-models/{name}", Role::kReader, "One shape model: categories, options, training report",
      [&s](Req, const PathParams& p) { return JsonResponse(ToJson(s.Get(p["name"]))); });
  router.Add("DELETE", "/v1/shape-models/{name}", Role::kWriter, "Delete a shape model",
      [&s](Req, const PathParams& p) {
        s.Delete(p["name"]);
        return JsonResponse({{"deleted", p["name"]}});
      });
  router.Add("POST", "/v1/shape-models/{name}:classify", Role::kReader,
      "Verification mode: the category distribution p(f) of one segment (PCD or PLY body, metres, z up) from the "
      "rays through one sphere at its centroid, weighted by how likely its size (height along z; length and width) "
      "is for each category's training clouds",
      [&s](Req req, const PathParams& p) { return JsonResponse(ToJson(s.Classify(p["name"], req.body))); });
  router.Add("POST", "/v1/shape-models/{name}:detect", Role::kReader,
      "Detection mode: furniture in a scene cloud (PCD or PLY body, metres): spheres >= 75 % of the global maximum, "
      "neighbours of a category merged, strongest first",
      [&s](Req req, const PathParams& p) { return JsonResponse(ToJson(s.Detect(p["name"], req.body))); });
}

}  // namespace anchordb::api
