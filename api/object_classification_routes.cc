// Routes of object classification: parse (api/object_classification_json.h), call ClassifierService::ClassifyInstance,
// serialise.
#include "api/object_classification_routes.h"

#include "api/object_classification_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace params;

void RegisterObjectClassificationRoutes(Router& router, services::ClassifierService& c) {
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:classify", Role::kWriter,
      "Classify an object instance from its newest segment with a trained classifier ({\"classifier\"}): the "
      "classifier's feature types extracted from the segment's points, bags of words over the map's codebooks, the "
      "class distribution stored with source classifier; it is the instance's label only when no dialog or operator "
      "label exists",
      [&c](const httplib::Request& req, const PathParams& p) {
        const auto request = ParseClassifyInstanceRequest(p["map"], PathId(p, "instance", "instance"), json::ParseObject(req.body));
        return JsonResponse(ToJson(c.ClassifyInstance(request)));
      });
}

}  // namespace anchordb::api
