// Routes of anchored features (SPEC §4.6, §5): parse (api/feature_json.h), call one FeatureService function, serialise.
#include "api/feature_routes.h"

#include "api/feature_json.h"
#include "api/job_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

void RegisterFeatureRoutes(Router& router, FeatureService& f) {
  using Req = const httplib::Request&;
  RegisterJobDocumentWriters("codebook",
      {[](const std::string& d, const std::string& what) { return ToJson(storage::DecodeCodebookRequest(d, what)); },
       [](const std::string& d, const std::string& what) { return ToJson(storage::DecodeCodebookResult(d, what)); }});
  router.Add("POST", "/v1/maps/{map}/features", Role::kWriter,
      "A client batch of anchored features of one type ({type, stamp?, features: [{descriptor, anchor_m, keyframe?}]}), "
      "de-duplicated against stored ones (close in descriptor space and 3D); ids per item",
      [&f](Req req, const PathParams& p) {
        const FeatureBatch batch = ParseFeatureBatch(json::ParseObject(req.body));
        return JsonResponse(ToJson(f.AddBatch(p["map"], batch)));
      });
  router.Add("GET", "/v1/maps/{map}/features", Role::kReader,
      "Anchored features (type=, near=x,y,z&radius=, bbox=, since=, until=, keyframe=, after=, limit=, descriptors=)",
      [&f](Req req, const PathParams& p) { return JsonResponse(ToJson(f.List(p["map"], ParseFeatureQuery(req)))); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:extract", Role::kWriter,
      "Extract fpfh, shot and spd features from a keyframe's cloud ({\"types\"?}) and store them de-duplicated",
      [&f](Req req, const PathParams& p) {
        const ExtractRequest r = ParseExtractRequest(BodyObject(req));
        return JsonResponse(ToJson(f.ExtractKeyframe(p["map"], PathId(p, "keyframe", "keyframe"), r)));
      });
  router.Add("POST", "/v1/maps/{map}/codebooks", Role::kWriter,
      "Build the codebook of a feature type by k-means ({type, words, seed}) and assign every feature its codeword; "
      "202 with the job",
      [&f](Req req, const PathParams& p) {
        return JsonResponse(ToJson(f.SubmitCodebook(p["map"], ParseCodebookRequest(json::ParseObject(req.body)))), 202);
      });
  router.Add("GET", "/v1/maps/{map}/codebooks/{type}", Role::kReader, "A codebook (centres=true for the centres)",
      [&f](Req req, const PathParams& p) {
        return JsonResponse(ToJson(f.GetCodebook(p["map"], p["type"]), QueryTrueFalse(req, "centres", false)));
      });
  router.Add("GET", "/v1/maps/{map}/bow", Role::kReader,
      "Bag of words (normalised codeword histogram) of the features of type= inside near=&radius=, bbox= or polygon=",
      [&f](Req req, const PathParams& p) { return JsonResponse(ToJson(f.BagOfWords(p["map"], ParseBowQuery(req)))); });
}

}  // namespace anchordb::api
