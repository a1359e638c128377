#pragma once
// The HTTP surface: the route table (api/router.h) every capability registers into, mounted on a cpp-httplib
// server with the conventions of SPEC §5 applied to every route in one place: JSON errors, auth by Bearer token
// and role, request ids in the log and in X-Request-Id, metrics per route, one catch-all per request.
#include "api/metrics.h"
#include "api/router.h"
#include "schema/error.h"
#include "schema/json_io.h"

#include <atomic>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace anchordb::api {

using json::Json;

struct HttpOptions {
  bool auth_required = false;
  // Returns the id and role of a presented token, or nullopt if the token is unknown.
  std::function<std::optional<Caller>(const std::string& token)> authenticate;
  // Receives one line per request (and per error) for the log.
  std::function<void(const std::string& line)> log;
  // The settings document served by GET /v1/settings.
  std::function<Json()> settings;
  // More Prometheus text appended to GET /metrics (the server's connection and queue counters); may be empty.
  std::function<std::string()> extra_metrics;
  std::size_t max_body_bytes = 64u << 20;
  // Write requests (routes of the writer or admin role) in service at once; one more is refused at once with 503 +
  // Retry-After. Effective only below the number of HTTP workers (the server's default: 24 of 32).
  int max_pending_writes = 24;
};

class HttpApi {
 public:
  // Registers the system routes (health, metrics, openapi, settings); capabilities register theirs into router().
  explicit HttpApi(HttpOptions options);

  Router& router() { return router_; }
  const std::vector<Route>& routes() const { return router_.routes(); }
  Metrics& metrics() { return metrics_; }
  // Registers every route and the error handler on `server`.
  void Mount(httplib::Server& server);

  // The OpenAPI document served at /v1/openapi.json (api/openapi.json, embedded at build time).
  static const std::string& OpenApiDocument();

 private:
  void AddSystemRoutes();
  void Dispatch(const Route& route, const std::vector<std::string>& names, const httplib::Request& req,
                httplib::Response& res);

  HttpOptions options_;
  Metrics metrics_;
  Router router_;
  std::atomic<int> writes_in_flight_{0};
};

// JSON error body {"error":{"code","message","field"}} and its status.
int HttpStatusFor(ErrorCode code);
std::string ErrorBody(ErrorCode code, const std::string& message, const std::string& field);

}  // namespace anchordb::api
