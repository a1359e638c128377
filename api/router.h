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

class Router {
 public:
  void Add(std::string method, std::string pattern, Role role, std::string summary, Handler handler);
  const std::vector<Route>& routes() const { return routes_; }

 private:
  std::vector<Route> routes_;
};

}  // namespace anchordb::api
