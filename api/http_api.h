#pragma once
// The HTTP surface: a table of routes (method, pattern, role, summary, handler), mounted on a cpp-httplib
// server with the conventions of SPEC §5 applied to every route in one place: JSON errors, auth by Bearer token
// and role, request ids in the log and in X-Request-Id, metrics per route, one catch-all per request.
// Eigen must come before httplib.h: httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include "api/event_service.h"
#include "api/furniture_service.h"
#include "api/grid_service.h"
#include "api/job_service.h"
#include "api/metrics.h"
#include "api/scene_service.h"
#include "schema/error.h"

#include <httplib.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace anchordb::api {

enum class Role { kPublic = 0, kReader = 1, kWriter = 2, kAdmin = 3 };
std::optional<Role> RoleFromName(std::string_view name);
const char* RoleName(Role role);

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::map<std::string, std::string> headers;
};

// Values of the {name} segments of a route pattern.
class PathParams {
 public:
  PathParams(std::vector<std::string> names, std::vector<std::string> values);
  const std::string& operator[](const std::string& name) const;

 private:
  std::vector<std::string> names_;
  std::vector<std::string> values_;
};

using Handler = std::function<Response(const httplib::Request&, const PathParams&)>;

struct Route {
  std::string method;   // GET, POST, PUT, DELETE
  std::string pattern;  // "/v1/maps/{map}/layers/{layer}"
  Role role = Role::kReader;
  std::string summary;
  Handler handler;
};

struct HttpOptions {
  bool auth_required = false;
  // Returns the role of a presented token, or nullopt if the token is unknown.
  std::function<std::optional<Role>(const std::string& token)> authenticate;
  // Receives one line per request (and per error) for the log.
  std::function<void(const std::string& line)> log;
  // The settings document served by GET /v1/settings.
  std::function<Json()> settings;
  std::size_t max_body_bytes = 64u << 20;
};

class HttpApi {
 public:
  HttpApi(GridService& grid, SceneService& scenes, FurnitureService& furniture, EventService& events, JobService& jobs,
          HttpOptions options);

  const std::vector<Route>& routes() const { return routes_; }
  Metrics& metrics() { return metrics_; }
  // Registers every route and the error handler on `server`.
  void Mount(httplib::Server& server);

  // The OpenAPI document served at /v1/openapi.json (api/openapi.json, embedded at build time).
  static const std::string& OpenApiDocument();

 private:
  void AddRoutes();
  void AddSceneRoutes();
  void AddFurnitureRoutes();
  void AddEventRoutes();
  void AddJobRoutes();  // api/job_routes.cc
  void Add(std::string method, std::string pattern, Role role, std::string summary, Handler handler);
  void Dispatch(const Route& route, const std::vector<std::string>& names, const httplib::Request& req,
                httplib::Response& res);

  GridService& service_;
  SceneService& scenes_;
  FurnitureService& furniture_;
  EventService& events_;
  JobService& jobs_;
  HttpOptions options_;
  Metrics metrics_;
  std::vector<Route> routes_;
};

// JSON error body {"error":{"code","message","field"}} and its status.
int HttpStatusFor(ErrorCode code);
std::string ErrorBody(ErrorCode code, const std::string& message, const std::string& field);

}  // namespace anchordb::api
