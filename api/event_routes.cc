// Routes of change events, instances, the where-is question and keyframe operations (SPEC §4.4, §5): parse
// (api/event_json.h), call one EventService function, serialise.
#include "api/event_routes.h"

#include "api/event_json.h"
#include "api/route_params.h"
#include "services/events/analysis_queue.h"
#include "services/events/event_service.h"

namespace anchordb::api {

using namespace anchordb::services;
using namespace params;

namespace {

std::int64_t EventId(const PathParams& p) { return PathId(p, "event", "event"); }
std::int64_t InstanceId(const PathParams& p) { return PathId(p, "instance", "instance"); }
std::int64_t KeyframeId(const PathParams& p) { return PathId(p, "keyframe", "keyframe"); }

}  // namespace

void RegisterEventRoutes(Router& router, EventService& e) {
  using Req = const httplib::Request&;
  router.Add("GET", "/v1/maps/{map}/events", Role::kReader,
      "Change events in time order (since=, until=, type=, instance=, scene=, after=, limit=)",
      [&e](Req req, const PathParams& p) { return JsonResponse(EventPageJson(e.ListEvents(p["map"], ParseEventQuery(req)))); });
  router.Add("GET", "/v1/maps/{map}/events/{event}", Role::kReader, "One event with its evidence keyframes",
      [&e](Req, const PathParams& p) { return JsonResponse(EventJson(e.GetEvent(p["map"], EventId(p)))); });
  router.Add("POST", "/v1/maps/{map}/events/{event}:label", Role::kWriter,
      "Label the object an event concerns, from dialog ({\"label\"}; source dialog|operator)",
      [&e](Req req, const PathParams& p) {
        const LabelRequest r = ParseLabelRequest(json::ParseObject(req.body));
        return JsonResponse(LabelResultJson(e.LabelEvent(p["map"], EventId(p), r)));
      });
  router.Add("DELETE", "/v1/maps/{map}/events/{event}", Role::kAdmin,
      "Operator deletes a wrong event with its evidence links (audited); answers the event as it was",
      [&e](Req, const PathParams& p) { return JsonResponse(EventJson(e.DeleteEvent(p["map"], EventId(p)))); });
  router.Add("GET", "/v1/maps/{map}/instances", Role::kReader, "Instances (label=, kind=, status=, after=, limit=)",
      [&e](Req req, const PathParams& p) { return JsonResponse(InstancePageJson(e.ListInstances(p["map"], ParseInstanceQuery(req)))); });
  router.Add("POST", "/v1/maps/{map}/instances", Role::kWriter,
      "Enter an instance by hand (furniture for where-is sentences): {kind, label, position, extent, yaw_rad}",
      [&e](Req req, const PathParams& p) {
        const CreateInstanceRequest r = ParseCreateInstanceRequest(json::ParseObject(req.body));
        return JsonResponse(InstanceJson(e.CreateInstance(p["map"], r)), 201);
      });
  router.Add("GET", "/v1/maps/{map}/instances/{instance}", Role::kReader, "One instance",
      [&e](Req, const PathParams& p) { return JsonResponse(InstanceJson(e.GetInstance(p["map"], InstanceId(p)))); });
  router.Add("GET", "/v1/maps/{map}/instances/{instance}/history", Role::kReader, "Every position an instance was known at",
      [&e](Req, const PathParams& p) { return JsonResponse(HistoryJson(e.History(p["map"], InstanceId(p)))); });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:label", Role::kWriter,
      "Label an instance ({\"label\", \"source\": dialog|operator}; an operator's label is never changed automatically)",
      [&e](Req req, const PathParams& p) {
        const LabelRequest r = ParseLabelRequest(json::ParseObject(req.body));
        return JsonResponse(LabelResultJson(e.LabelInstance(p["map"], InstanceId(p), r)));
      });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:pin", Role::kWriter, "Pin an instance: forgetting keeps its history",
      [&e](Req, const PathParams& p) { return JsonResponse(InstanceJson(e.PinInstance(p["map"], InstanceId(p), true))); });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:unpin", Role::kWriter, "Unpin an instance",
      [&e](Req, const PathParams& p) { return JsonResponse(InstanceJson(e.PinInstance(p["map"], InstanceId(p), false))); });
  router.Add("DELETE", "/v1/maps/{map}/instances/{instance}", Role::kAdmin,
      "Delete an instance (kept as a tombstone so its events stay consistent; never revived)",
      [&e](Req, const PathParams& p) { return JsonResponse(InstanceJson(e.DeleteInstance(p["map"], InstanceId(p)))); });
  router.Add("GET", "/v1/maps/{map}/where", Role::kReader,
      "Where is the thing labelled label= (at= a past time): position, time, evidence, confidence, sentence",
      [&e](Req req, const PathParams& p) { return JsonResponse(WhereJson(e.Where(p["map"], ParseWhereRequest(req)))); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:pin", Role::kWriter, "Pin a keyframe: forgetting keeps it",
      [&e](Req, const PathParams& p) { return JsonResponse(KeyframePinnedJson(e.PinKeyframe(p["map"], KeyframeId(p), true))); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:unpin", Role::kWriter, "Unpin a keyframe",
      [&e](Req, const PathParams& p) { return JsonResponse(KeyframePinnedJson(e.PinKeyframe(p["map"], KeyframeId(p), false))); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:score", Role::kWriter,
      "Set a keyframe's relevance in [0, 1] (a high-level component's judgement; forgetting keeps relevant ones)",
      [&e](Req req, const PathParams& p) {
        const double relevance = ParseRelevance(json::ParseObject(req.body));
        return JsonResponse(KeyframeRelevanceJson(e.SetKeyframeRelevance(p["map"], KeyframeId(p), relevance)));
      });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:reanalyse", Role::kWriter,
      "Apply a newer scene model's background ({\"scene\"}, default the newest of the place) to an old keyframe",
      [&e](Req req, const PathParams& p) {
        const ReanalyseRequest r = ParseReanalyseRequest(BodyObject(req));
        return JsonResponse(ReanalyseJson(e.Reanalyse(p["map"], KeyframeId(p), r)));
      });
}

void RegisterAnalysisRoutes(Router& router, AnalysisQueue& q) {
  router.Add("GET", "/v1/maps/{map}/analysis", Role::kReader,
      "The map's queue of keyframe change analyses: depth, running, retrying, failed, oldest pending age, failures",
      [&q](const httplib::Request&, const PathParams& p) { return JsonResponse(AnalysisQueueJson(q.View(p["map"]))); });
}

}  // namespace anchordb::api
