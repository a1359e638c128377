#include "api/audit_routes.h"

#include <memory>
#include <mutex>
#include <regex>

#include "api/audit_json.h"
#include "api/route_params.h"

namespace anchordb::api {

using namespace params;

const std::vector<AuditedAction>& AuditedActions() {
  static const char* kInstance = "/v1/maps/{map}/instances/{instance}";
  static const char* kKeyframe = "/v1/maps/{map}/keyframes/{keyframe}";
  static const std::vector<AuditedAction> kActions = {
      {"POST", "/v1/maps/{map}/instances/{instance}:label", "instance.label", kInstance},
      {"POST", "/v1/maps/{map}/instances/{instance}:pin", "instance.pin", kInstance},
      {"POST", "/v1/maps/{map}/instances/{instance}:unpin", "instance.unpin", kInstance},
      {"POST", "/v1/maps/{map}/instances/{instance}:classify", "instance.classify", kInstance},
      {"DELETE", "/v1/maps/{map}/instances/{instance}", "instance.delete", kInstance},
      {"POST", "/v1/maps/{map}/instances", "instance.create", nullptr, true},
      {"POST", "/v1/maps/{map}/events/{event}:label", "event.label", "/v1/maps/{map}/events/{event}"},
      {"DELETE", "/v1/maps/{map}/events/{event}", "event.delete", "/v1/maps/{map}/events/{event}"},
      {"POST", "/v1/maps/{map}/keyframes/{keyframe}:pin", "keyframe.pin", kKeyframe},
      {"POST", "/v1/maps/{map}/keyframes/{keyframe}:unpin", "keyframe.unpin", kKeyframe},
      {"POST", "/v1/maps/{map}/keyframes/{keyframe}:score", "keyframe.score", kKeyframe},
      {"DELETE", "/v1/maps/{map}", "map.delete", "/v1/maps/{map}"},
      {"DELETE", "/v1/maps/{map}/layers/{layer}", "layer.delete", nullptr},
      {"POST", "/v1/maps/{map}:forget", "map.forget", nullptr, true},
      {"POST", "/v1/backups", "backup.create", nullptr, true},
      {"POST", "/v1/maps/{map}/octomap:clear", "octomap.clear", "/v1/maps/{map}/octomap"},
      {"POST", "/v1/maps/{map}/octomap:decay", "octomap.decay", "/v1/maps/{map}/octomap"},
  };
  return kActions;
}

namespace {

std::vector<std::string> PatternNames(const std::string& pattern) {
  static const std::regex kParam(R"(\{([a-z_]+)\})");
  std::vector<std::string> names;
  for (auto it = std::sregex_iterator(pattern.begin(), pattern.end(), kParam); it != std::sregex_iterator(); ++it) {
    names.push_back((*it)[1].str());
  }
  return names;
}

class AuditTrail {
 public:
  AuditTrail(const Router& router, services::AuditService& audit) : router_(router), audit_(audit) {}

  Response Observe(const Route& route, const Caller& caller, const RequestContext& ctx, const std::function<Response()>& call) {
    const AuditedAction* action = Find(route);
    // Reads are not actions: an admin's GET (a dashboard polling /metrics, this very route) writes no entry.
    if (!action && (caller.role != Role::kAdmin || route.method == "GET")) return call();
    std::unique_lock<std::mutex> one_edit_at_a_time(edits_, std::defer_lock);
    if (action && action->snapshot_pattern) one_edit_at_a_time.lock();
    services::AuditEntry entry;
    entry.actor = caller.token_id;
    entry.role = caller.role ? RoleName(*caller.role) : "";
    entry.action = action ? action->action : route.method + " " + route.pattern;
    entry.request_id = ctx.request_id;
    for (std::size_t i = 0; i < ctx.param_names.size() && i < ctx.param_values.size(); ++i) {
      if (ctx.param_names[i] == "map") entry.map = ctx.param_values[i];
      else entry.resource += (entry.resource.empty() ? "" : ",") + ctx.param_names[i] + "=" + ctx.param_values[i];
    }
    const bool snapshots = action && action->snapshot_pattern;
    if (snapshots) entry.before_json = Snapshot(action->snapshot_pattern, ctx);
    services::AuditService::InFlight in_flight = audit_.Begin(std::move(entry));
    // Completing the entry is a write of its own after the change: when the storage fails it (disk full, I/O error),
    // the answer stays the change's own (the change is committed or not regardless); the entry then keeps status 0,
    // "outcome not recorded", as after a crash between the change and its answer.
    const auto finish = [&](int status, std::optional<std::string> after) {
      services::AuditService::Disarm();
      try {
        if (snapshots) after = Snapshot(action->snapshot_pattern, ctx);
        audit_.Finish(in_flight, status, std::move(after));
      } catch (const Error& e) {
        if (e.code() != ErrorCode::kUnavailable && e.code() != ErrorCode::kInsufficientStorage && e.code() != ErrorCode::kOverloaded) throw;
      }
    };
    Response out;
    try {
      out = call();
    } catch (const Error& e) {
      finish(HttpStatusFor(e.code()), std::nullopt);
      throw;
    } catch (...) {
      finish(500, std::nullopt);
      throw;
    }
    const bool body_is_after = action && action->response_is_after && out.content_type == "application/json";
    finish(out.status, body_is_after ? std::optional<std::string>(out.body) : std::nullopt);
    return out;
  }

 private:
  const AuditedAction* Find(const Route& route) const {
    for (const AuditedAction& a : AuditedActions()) {
      if (route.method == a.method && route.pattern == a.pattern) return &a;
    }
    return nullptr;
  }

  // The record the GET route `pattern` answers for the request's path values, or nullopt when it has none (404).
  std::optional<std::string> Snapshot(const std::string& pattern, const RequestContext& ctx) const {
    for (const Route& r : router_.routes()) {
      if (r.method != "GET" || r.pattern != pattern) continue;
      std::vector<std::string> names = PatternNames(pattern), values;
      for (const std::string& name : names) {
        for (std::size_t i = 0; i < ctx.param_names.size(); ++i) {
          if (ctx.param_names[i] == name) values.push_back(ctx.param_values[i]);
        }
      }
      if (values.size() != names.size()) return std::nullopt;
      try {
        Response got = r.handler(httplib::Request{}, PathParams(names, values));
        if (got.status == 200 && got.content_type == "application/json") return got.body;
      } catch (const Error&) {
      }
      return std::nullopt;
    }
    return std::nullopt;
  }

  const Router& router_;
  services::AuditService& audit_;
  std::mutex edits_;
};

}  // namespace

void RegisterAuditRoutes(Router& router, services::AuditService& audit) {
  router.Add("GET", "/v1/audit", Role::kAdmin,
             "Operator and admin actions, oldest first (since=, until=, actor=, action=, map=, after=, limit=)",
             [&audit](const httplib::Request& req, const PathParams&) {
               return JsonResponse(AuditPageJson(audit.List(ParseAuditQuery(req))));
             });
  auto trail = std::make_shared<AuditTrail>(router, audit);
  router.SetObserver([trail](const Route& route, const Caller& caller, const RequestContext& ctx,
                             const std::function<Response()>& call) { return trail->Observe(route, caller, ctx, call); });
}

}  // namespace anchordb::api
