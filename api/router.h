#pragma once
// The route table every capability registers into: method, pattern, role, summary and a thin handler (parse the
// request into a typed request, call one service function, serialise its typed result). Each capability has one
// `Register<Capability>Routes(Router&, Service&)` in its `*_routes.h`; server/ composes them.
// Eigen must come before httplib.h: httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <Eigen/Core>

#include <httplib.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
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
  // A streamed body instead of `body` (Server-Sent Events): called again and again, chunked, until it calls
  // sink.done() or returns false (peer gone, error); the server's stop ends it between calls. It writes with
  // sink.write and sends what it wrote with sink.is_writable() (the server flushes there). Whatever it captures lives
  // until the response is finished.
  std::function<bool(httplib::DataSink& sink)> stream;
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
  // Changes the memory: counted against the admission limit (503 + Retry-After beyond it). Every route that needs
  // the writer or admin role.
  bool write = false;
};

// Who made a request: the token's id and role, or "loopback" without a role when the server runs without auth.
struct Caller {
  std::string token_id = "loopback";
  std::optional<Role> role;
};

// What an observer sees of a request besides its route: the request, its id (X-Request-Id) and the path values.
struct RequestContext {
  const httplib::Request& request;
  const std::string& request_id;
  const std::vector<std::string>& param_names;
  const std::vector<std::string>& param_values;
};

// Runs around every handler once the caller is authorised (the audit trail, api/audit_routes.h): `call` runs the
// handler; the observer returns its response and lets its errors through.
using RequestObserver =
    std::function<Response(const Route&, const Caller&, const RequestContext&, const std::function<Response()>& call)>;

class Router {
 public:
  void Add(std::string method, std::string pattern, Role role, std::string summary, Handler handler);
  const std::vector<Route>& routes() const { return routes_; }
  void SetObserver(RequestObserver observer) { observer_ = std::move(observer); }
  const RequestObserver& observer() const { return observer_; }

 private:
  std::vector<Route> routes_;
  RequestObserver observer_;
};

}  // namespace anchordb::api
