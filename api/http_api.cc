#include "api/http_api.h"

#include <atomic>
#include <chrono>
#include <random>
#include <regex>

#include "schema/error.h"

namespace anchordb::api {

std::optional<Role> RoleFromName(std::string_view name) {
  if (name == "reader") return Role::kReader;
  if (name == "writer") return Role::kWriter;
  if (name == "admin") return Role::kAdmin;
  return std::nullopt;
}

const char* RoleName(Role role) {
  switch (role) {
    case Role::kPublic: return "public";
    case Role::kReader: return "reader";
    case Role::kWriter: return "writer";
    case Role::kAdmin: return "admin";
  }
  return "public";
}

int HttpStatusFor(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidJson: return 400;
    case ErrorCode::kInvalidArgument: return 400;
    case ErrorCode::kUnprocessable: return 422;
    case ErrorCode::kNotFound: return 404;
    case ErrorCode::kConflict: return 409;
    case ErrorCode::kUnauthenticated: return 401;
    case ErrorCode::kForbidden: return 403;
    case ErrorCode::kPayloadTooLarge: return 413;
    case ErrorCode::kUnsupportedMediaType: return 415;
    case ErrorCode::kOverloaded: return 503;
    case ErrorCode::kInternal: return 500;
  }
  return 500;
}

std::string ErrorBody(ErrorCode code, const std::string& message, const std::string& field) {
  Json e = {{"code", ErrorCodeName(code)}, {"message", message}};
  e["field"] = field.empty() ? Json(nullptr) : Json(field);
  return Json{{"error", e}}.dump();
}

PathParams::PathParams(std::vector<std::string> names, std::vector<std::string> values)
    : names_(std::move(names)), values_(std::move(values)) {}

const std::string& PathParams::operator[](const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return values_[i];
  }
  throw Error(ErrorCode::kInternal, "route has no path parameter '" + name + "'");
}

HttpApi::HttpApi(GridService& grid, SceneService& scenes, FurnitureService& furniture, EventService& events,
                 JobService& jobs, HttpOptions options)
    : service_(grid), scenes_(scenes), furniture_(furniture), events_(events), jobs_(jobs), options_(std::move(options)) {
  AddRoutes();
  AddSceneRoutes();
  AddFurnitureRoutes();
  AddEventRoutes();
  AddJobRoutes();
}

void HttpApi::Add(std::string method, std::string pattern, Role role, std::string summary, Handler handler) {
  routes_.push_back({std::move(method), std::move(pattern), role, std::move(summary), std::move(handler)});
}

namespace {

std::string NextRequestId() {
  static std::atomic<std::uint64_t> counter{std::random_device{}() & 0xffffff};
  char buf[24];
  std::snprintf(buf, sizeof(buf), "r%010llx", static_cast<unsigned long long>(++counter));
  return buf;
}

bool IsSafeRequestId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) return false;
  }
  return true;
}

void SetError(httplib::Response& res, ErrorCode code, const std::string& message, const std::string& field) {
  res.status = HttpStatusFor(code);
  res.set_content(ErrorBody(code, message, field), "application/json");
}

}  // namespace

void HttpApi::Dispatch(const Route& route, const std::vector<std::string>& names, const httplib::Request& req,
                       httplib::Response& res) {
  const auto start = std::chrono::steady_clock::now();
  std::string request_id = req.get_header_value("X-Request-Id");
  if (!IsSafeRequestId(request_id)) request_id = NextRequestId();
  res.set_header("X-Request-Id", request_id);
  const std::string route_key = route.method + " " + route.pattern;
  std::string log_detail;
  try {
    // cpp-httplib checks its payload limit against Content-Length only; a chunked body is checked here.
    if (req.body.size() > options_.max_body_bytes) {
      throw Error(ErrorCode::kPayloadTooLarge, "request body exceeds " + std::to_string(options_.max_body_bytes) + " bytes");
    }
    if (options_.auth_required && route.role != Role::kPublic) {
      const std::string header = req.get_header_value("Authorization");
      if (header.rfind("Bearer ", 0) != 0 || header.size() <= 7) {
        throw Error(ErrorCode::kUnauthenticated, "this server requires a Bearer token (Authorization: Bearer <token>)");
      }
      const auto role = options_.authenticate ? options_.authenticate(header.substr(7)) : std::nullopt;
      if (!role) throw Error(ErrorCode::kUnauthenticated, "the Bearer token is not known to this server");
      if (static_cast<int>(*role) < static_cast<int>(route.role)) {
        throw Error(ErrorCode::kForbidden, std::string("this route needs the ") + RoleName(route.role) +
                                               " role; the token has " + RoleName(*role));
      }
    }
    std::vector<std::string> values;
    for (std::size_t i = 1; i < req.matches.size(); ++i) {
      values.push_back(req.matches[i].str());
      json::CheckId(values.back(), names[i - 1]);  // the route regex admits the characters; this checks the rest
    }
    Response out = route.handler(req, PathParams(names, std::move(values)));
    res.status = out.status;
    for (const auto& [k, v] : out.headers) res.set_header(k, v);
    res.set_content(std::move(out.body), out.content_type);
  } catch (const Error& e) {
    SetError(res, e.code(), e.what(), e.field());
    if (e.code() == ErrorCode::kUnauthenticated) res.set_header("WWW-Authenticate", "Bearer");
    log_detail = std::string(" error=") + ErrorCodeName(e.code()) + " message=\"" + e.what() + "\"";
  } catch (const std::bad_alloc&) {
    SetError(res, ErrorCode::kOverloaded, "out of memory while handling the request", "");
    log_detail = " error=bad_alloc";
  } catch (const std::exception& e) {
    SetError(res, ErrorCode::kInternal, "internal error (request " + request_id + ")", "");
    log_detail = std::string(" error=internal what=\"") + e.what() + "\"";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  metrics_.Record(route_key, res.status, seconds);
  if (options_.log) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), " %.3fms", seconds * 1e3);
    options_.log("request_id=" + request_id + " " + req.method + " " + req.path + " status=" +
                 std::to_string(res.status) + buf + log_detail);
  }
}

void HttpApi::Mount(httplib::Server& server) {
  static const std::regex kParam(R"(\{([a-z_]+)\})");
  for (const Route& route : routes_) {
    std::vector<std::string> names;
    for (auto it = std::sregex_iterator(route.pattern.begin(), route.pattern.end(), kParam); it != std::sregex_iterator(); ++it) {
      names.push_back((*it)[1].str());
    }
    const std::string regex = std::regex_replace(route.pattern, kParam, "([A-Za-z0-9_.\\-]+)");
    auto handler = [this, &route, names](const httplib::Request& req, httplib::Response& res) {
      Dispatch(route, names, req, res);
    };
    if (route.method == "GET") server.Get(regex, handler);
    else if (route.method == "POST") server.Post(regex, handler);
    else if (route.method == "PUT") server.Put(regex, handler);
    else if (route.method == "DELETE") server.Delete(regex, handler);
  }
  server.set_payload_max_length(options_.max_body_bytes);
  server.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a route already wrote its JSON error
    ErrorCode code = res.status >= 500 ? ErrorCode::kInternal : ErrorCode::kInvalidArgument;
    std::string message = "request failed with HTTP status " + std::to_string(res.status);
    const bool form = req.get_header_value("Content-Type").rfind("application/x-www-form-urlencoded", 0) == 0;
    if (res.status == 404) code = ErrorCode::kNotFound, message = "no route " + req.method + " " + req.path;
    else if (res.status == 413 && form) {
      code = ErrorCode::kPayloadTooLarge;
      message = "bodies sent as application/x-www-form-urlencoded are limited to 8192 bytes by the HTTP library; "
                "send JSON with Content-Type: application/json";
    } else if (res.status == 413) code = ErrorCode::kPayloadTooLarge, message = "request body exceeds " + std::to_string(options_.max_body_bytes) + " bytes";
    else if (res.status == 400) code = ErrorCode::kInvalidArgument, message = "malformed HTTP request";
    else if (res.status == 415) code = ErrorCode::kUnsupportedMediaType, message = "unsupported media type";
    const int status = res.status;
    res.set_content(ErrorBody(code, message, ""), "application/json");
    res.status = status;
    std::string request_id = req.get_header_value("X-Request-Id");
    if (!IsSafeRequestId(request_id)) request_id = NextRequestId();
    res.set_header("X-Request-Id", request_id);
    if (options_.log) options_.log(req.method + " " + req.path + " status=" + std::to_string(status) + " error=" + ErrorCodeName(code));
  });
}

}  // namespace anchordb::api
