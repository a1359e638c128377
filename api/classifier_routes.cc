// Routes of trained classifiers: parse (api/classifier_json.h), call one ClassifierService function, serialise.
#include "api/classifier_routes.h"

#include "api/classifier_documents_json.h"
#include "api/classifier_json.h"
#include "api/job_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

void RegisterClassifierRoutes(Router& router, ClassifierService& c) {
  RegisterClassifierJobDocumentWriters();
  using Req = const httplib::Request&;
  router.Add("POST", "/v1/classifiers", Role::kWriter,
      "Train an E-SAMME classifier as a job (k-fold cross-validation report, then the model on every sample); 202 with the job",
      [&c](Req req, const PathParams&) {
        return JsonResponse(ToJson(c.SubmitTraining(ParseTrainClassifierRequest(json::ParseObject(req.body)))), 202);
      });
  router.Add("GET", "/v1/classifiers", Role::kReader, "Trained classifiers with their reports",
      [&c](Req, const PathParams&) {
        Json list = Json::array();
        for (const auto& v : c.List()) list.push_back(ToJson(v));
        return JsonResponse({{"classifiers", list}});
      });
  router.Add("GET", "/v1/classifiers/{name}", Role::kReader, "One classifier: classes, feature types, options, report",
      [&c](Req, const PathParams& p) { return JsonResponse(ToJson(c.Get(p["name"]))); });
  router.Add("POST", "/v1/maps/{map}/rooms:classify", Role::kWriter,
      "Room categories of regions from the bags of words of their features ({classifier, regions: [{id, polygon}], into?}); "
      "with into, the most probable category is painted into that label layer",
      [&c](Req req, const PathParams& p) {
        return JsonResponse(ToJson(c.ClassifyRooms(ParseClassifyRoomsRequest(p["map"], json::ParseObject(req.body)))));
      });
  router.Add("POST", "/v1/classifiers/{name}:predict", Role::kReader,
      "Class distributions of samples ({samples: [{features: {<type>: [...]}}], rounds?})",
      [&c](Req req, const PathParams& p) {
        return JsonResponse(ToJson(c.Predict(p["name"], ParsePredictRequest(json::ParseObject(req.body)))));
      });
}

}  // namespace anchordb::api
