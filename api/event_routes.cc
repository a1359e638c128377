// Routes of change events, instances, the where-is question and keyframe operations (SPEC §4.4, §5).
#include "api/event_routes.h"
#include "services/events/event_service.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace anchordb::services;

using namespace params;

void RegisterEventRoutes(Router& router, EventService& e) {
  router.Add("GET", "/v1/maps/{map}/events", Role::kReader,
      "Change events in time order (since=, until=, type=, instance=, scene=, after=, limit=)",
      [&e](const httplib::Request& req, const PathParams& p) {
        storage::EventFilter f;
        f.since_ns = QueryTime(req, "since");
        f.until_ns = QueryTime(req, "until");
        f.type = QueryChoice(req, "type", {"added", "removed", "moved", "labelled"});
        if (req.has_param("instance")) f.instance_id = QueryInteger(req, "instance", 0, 1, INT64_MAX);
        if (req.has_param("scene")) f.scene_id = QueryInteger(req, "scene", 0, 1, INT64_MAX);
        f.after_id = QueryInteger(req, "after", 0, 0, INT64_MAX);
        f.limit = static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000));
        return JsonResponse(e.ListEvents(p["map"], f));
      });
  router.Add("GET", "/v1/maps/{map}/events/{event}", Role::kReader, "One event with its evidence keyframes",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.GetEvent(p["map"], PathId(p, "event", "event"))); });
  router.Add("POST", "/v1/maps/{map}/events/{event}:label", Role::kWriter,
      "Label the object an event concerns, from dialog ({\"label\"}; source dialog|operator)",
      [&e](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(e.LabelEvent(p["map"], PathId(p, "event", "event"), json::ParseObject(req.body)));
      });
  router.Add("GET", "/v1/maps/{map}/instances", Role::kReader, "Instances (label=, kind=, status=, after=, limit=)",
      [&e](const httplib::Request& req, const PathParams& p) {
        storage::InstanceFilter f;
        f.kind = QueryChoice(req, "kind", {"object", "furniture"});
        f.status = QueryChoice(req, "status", {"present", "absent", "deleted"});
        f.after_id = QueryInteger(req, "after", 0, 0, INT64_MAX);
        f.limit = static_cast<int>(QueryInteger(req, "limit", 100, 1, 1000));
        return JsonResponse(e.ListInstances(p["map"], QueryString(req, "label", 256), f));
      });
  router.Add("POST", "/v1/maps/{map}/instances", Role::kWriter,
      "Enter an instance by hand (furniture for where-is sentences): {kind, label, position, extent, yaw_rad}",
      [&e](const httplib::Request& req, const PathParams& p) { return JsonResponse(e.CreateInstance(p["map"], json::ParseObject(req.body)), 201); });
  router.Add("GET", "/v1/maps/{map}/instances/{instance}", Role::kReader, "One instance",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.GetInstance(p["map"], PathId(p, "instance", "instance"))); });
  router.Add("GET", "/v1/maps/{map}/instances/{instance}/history", Role::kReader, "Every position an instance was known at",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.History(p["map"], PathId(p, "instance", "instance"))); });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:label", Role::kWriter,
      "Label an instance ({\"label\", \"source\": dialog|operator}; an operator's label is never changed automatically)",
      [&e](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(e.LabelInstance(p["map"], PathId(p, "instance", "instance"), json::ParseObject(req.body)));
      });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:pin", Role::kWriter, "Pin an instance: forgetting keeps its history",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.PinInstance(p["map"], PathId(p, "instance", "instance"), true)); });
  router.Add("POST", "/v1/maps/{map}/instances/{instance}:unpin", Role::kWriter, "Unpin an instance",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.PinInstance(p["map"], PathId(p, "instance", "instance"), false)); });
  router.Add("DELETE", "/v1/maps/{map}/instances/{instance}", Role::kAdmin,
      "Delete an instance (kept as a tombstone so its events stay consistent; never revived)",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.DeleteInstance(p["map"], PathId(p, "instance", "instance"))); });
  router.Add("GET", "/v1/maps/{map}/where", Role::kReader,
      "Where is the thing labelled label= (at= a past time): position, time, evidence, confidence, sentence",
      [&e](const httplib::Request& req, const PathParams& p) {
        const auto label = QueryString(req, "label", 256);
        if (!label) throw Error(ErrorCode::kInvalidArgument, "label is required", "label");
        return JsonResponse(e.Where(p["map"], *label, QueryTime(req, "at")));
      });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:pin", Role::kWriter, "Pin a keyframe: forgetting keeps it",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.PinKeyframe(p["map"], PathId(p, "keyframe", "keyframe"), true)); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:unpin", Role::kWriter, "Unpin a keyframe",
      [&e](const httplib::Request&, const PathParams& p) { return JsonResponse(e.PinKeyframe(p["map"], PathId(p, "keyframe", "keyframe"), false)); });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:score", Role::kWriter,
      "Set a keyframe's relevance in [0, 1] (a high-level component's judgement; forgetting keeps relevant ones)",
      [&e](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(e.SetKeyframeRelevance(p["map"], PathId(p, "keyframe", "keyframe"), json::ParseObject(req.body)));
      });
  router.Add("POST", "/v1/maps/{map}/keyframes/{keyframe}:reanalyse", Role::kWriter,
      "Apply a newer scene model's background ({\"scene\"}, default the newest of the place) to an old keyframe",
      [&e](const httplib::Request& req, const PathParams& p) {
        return JsonResponse(e.Reanalyse(p["map"], PathId(p, "keyframe", "keyframe"), BodyObject(req)));
      });
}

}  // namespace anchordb::api
