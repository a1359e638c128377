// Routes of long work (SPEC §5: long work returns 202 with a job; GET /v1/jobs/{id} shows progress and result).
#include "api/job_routes.h"

#include "api/job_json.h"
#include "api/request_limits.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

Response Accepted(const JobTicket& ticket) {
  Response r = JsonResponse(ToJson(ticket), 202);
  r.headers["Location"] = "/v1/jobs/" + std::to_string(ticket.job);
  return r;
}

}  // namespace

void RegisterJobRoutes(Router& router, JobService& j) {
  RegisterBuiltInJobDocumentWriters();
  router.Add("POST", "/v1/maps/{map}:forget", Role::kAdmin,
      "Forgetting as a job ({\"policy\": {superseded_models, keyframe_max_age_s, keep_relevance_at_least, "
      "event_max_age_s, vacuum}, \"dry_run\"}); 202 with the job",
      [&j](const httplib::Request& req, const PathParams& p) {
        return Accepted(j.SubmitForget(p["map"], ParseForgetRequest(BodyObject(req))));
      });
  router.Add("POST", "/v1/backups", Role::kAdmin,
      "Online backup of the whole database as a job ({\"label\"?}); the copy goes to the server's backup_dir and "
      "the job's result names the file; 202 with the job",
      [&j](const httplib::Request& req, const PathParams&) { return Accepted(j.SubmitBackup(ParseBackupRequest(BodyObject(req)))); });
  router.Add("POST", "/v1/jobs/{job}:cancel", Role::kWriter,
      "Cancel a queued or running job (it fails with the error \"cancelled\"); {\"cancelled\": false} when it had finished",
      [&j](const httplib::Request&, const PathParams& p) {
        return JsonResponse(Json{{"cancelled", j.Cancel(PathId(p, "job", "job"))}});
      });
  router.Add("GET", "/v1/jobs", Role::kReader,
      "Jobs, newest first (map=, before=, limit=): status, stage, progress, request, result, error",
      [&j](const httplib::Request& req, const PathParams&) {
        const auto map = QueryString(req, "map", limits::kIdLength);
        const int limit = QueryWholeNumber(req, "limit", 50, 1, 1000);
        Json out = Json::array();
        for (const JobView& v : j.List(map, QueryInteger(req, "before", 0, 0, INT64_MAX), limit)) {
          out.push_back(ToJson(v));
        }
        return JsonResponse(Json{{"jobs", out}});
      });
  router.Add("GET", "/v1/jobs/{job}", Role::kReader, "A job: status, stage, progress, request, result, error",
      [&j](const httplib::Request&, const PathParams& p) { return JsonResponse(ToJson(j.Get(PathId(p, "job", "job")))); });
}

}  // namespace anchordb::api
