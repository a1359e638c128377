#include "api/http_api.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <random>
#include <regex>
#include <string_view>

#include "api/request_limits.h"
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
    case ErrorCode::kUnavailable: return 503;
    case ErrorCode::kInsufficientStorage: return 507;
    case ErrorCode::kInternal: return 500;
  }
  return 500;
}

std::string ErrorBody(ErrorCode code, const std::string& message, const std::string& field) {
  Json e = {{"code", ErrorCodeName(code)}, {"message", message}};
  e["field"] = field.empty() ? Json(nullptr) : Json(field);
  // Messages may quote the request (a parser's "last read" bytes): bytes that are not UTF-8 become U+FFFD instead of
  // failing the whole answer.
  return Json{{"error", e}}.dump(-1, ' ', false, Json::error_handler_t::replace);
}

PathParams::PathParams(std::vector<std::string> names, std::vector<std::string> values)
    : names_(std::move(names)), values_(std::move(values)) {}

const std::string& PathParams::operator[](const std::string& name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return values_[i];
  }
  throw Error(ErrorCode::kInternal, "route has no path parameter '" + name + "'");
}

void Router::Add(std::string method, std::string pattern, Role role, std::string summary, Handler handler) {
  const bool write = role >= Role::kWriter;  // a reader's POST (viewpoints, :describe) computes, it changes nothing
  routes_.push_back({std::move(method), std::move(pattern), role, std::move(summary), std::move(handler), write});
}

HttpApi::HttpApi(HttpOptions options) : options_(std::move(options)) { AddSystemRoutes(); }

void HttpApi::AddSystemRoutes() {
  router_.Add("GET", "/v1/health", Role::kPublic, "Liveness", [](const auto&, const auto&) {
    return Response{200, "application/json", Json{{"status", "ok"}}.dump(), {}};
  });
  router_.Add("GET", "/metrics", Role::kReader, "Prometheus text: request counts and latency per route",
              [this](const auto&, const auto&) {
                std::string text = metrics_.Prometheus();
                if (options_.extra_metrics) text += options_.extra_metrics();
                return Response{200, "text/plain; version=0.0.4", std::move(text), {}};
              });
  router_.Add("GET", "/v1/openapi.json", Role::kPublic, "This API's OpenAPI 3 description", [](const auto&, const auto&) {
    return Response{200, "application/json", OpenApiDocument(), {}};
  });
  router_.Add("GET", "/v1/whoami", Role::kPublic,
              "The caller: its token id and role (what the console's edit controls follow); 401 for an unknown token",
              [this](const httplib::Request& req, const auto&) {
                Json out = {{"auth_required", options_.auth_required}, {"token", nullptr}, {"role", nullptr}};
                if (!options_.auth_required) {
                  out["token"] = "loopback", out["role"] = RoleName(Role::kAdmin);  // no role is checked
                } else if (const std::string h = req.get_header_value("Authorization"); h.rfind("Bearer ", 0) == 0 && h.size() > 7) {
                  const auto found = options_.authenticate ? options_.authenticate(h.substr(7)) : std::nullopt;
                  if (!found || !found->role) throw Error(ErrorCode::kUnauthenticated, "the Bearer token is not known to this server");
                  out["token"] = found->token_id, out["role"] = RoleName(*found->role);
                }
                return Response{200, "application/json", out.dump(), {}};
              });
  router_.Add("GET", "/v1/settings", Role::kReader, "Every server setting with its description and value",
              [this](const auto&, const auto&) {
                return Response{200, "application/json", (options_.settings ? options_.settings() : Json::object()).dump(), {}};
              });
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

// Whether `s` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF).
bool IsUtf8(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = p[i];
    std::size_t len = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) len = 1, cp = c;
    else if ((c & 0xE0) == 0xC0) len = 2, cp = c & 0x1F;
    else if ((c & 0xF0) == 0xE0) len = 3, cp = c & 0x0F;
    else if ((c & 0xF8) == 0xF0) len = 4, cp = c & 0x07;
    else return false;
    if (i + len > n) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((p[i + k] & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (p[i + k] & 0x3F);
    }
    static constexpr std::uint32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < kMin[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += len;
  }
  return true;
}

// A log line that cannot forge other lines or break a UTF-8 log reader: control characters, DEL and bytes of
// malformed UTF-8 (from a decoded path or a message quoting the request) become \xHH.
std::string LogSafe(const std::string& line) {
  std::string out;
  out.reserve(line.size());
  static constexpr char kHex[] = "0123456789abcdef";
  const auto escape = [&](unsigned char c) { out += "\\x", out += kHex[c >> 4], out += kHex[c & 15]; };
  for (std::size_t i = 0; i < line.size();) {
    const auto c = static_cast<unsigned char>(line[i]);
    if (c < 0x20 || c == 0x7f) {
      escape(c), ++i;
    } else if (c < 0x80) {
      out += static_cast<char>(c), ++i;
    } else {
      const std::size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
      if (len > 0 && i + len <= line.size() && IsUtf8(std::string_view(line).substr(i, len))) {
        out.append(line, i, len), i += len;
      } else {
        escape(c), ++i;
      }
    }
  }
  return out;
}

void SetError(httplib::Response& res, ErrorCode code, const std::string& message, const std::string& field) {
  res.status = HttpStatusFor(code);
  if (HttpStatusFor(code) == 503) res.set_header("Retry-After", "1");  // every 503 says when to come back
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
  // Admission control for every write path: a write beyond the limit is refused at once instead of queueing for the
  // writer (the client retries after Retry-After); counted in /metrics as anchordb_writes_refused_total.
  struct WriteSlot {
    std::atomic<int>* counter = nullptr;
    ~WriteSlot() { if (counter) --*counter; }
  } slot;
  Caller caller;
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
      const auto found = options_.authenticate ? options_.authenticate(header.substr(7)) : std::nullopt;
      if (!found || !found->role) throw Error(ErrorCode::kUnauthenticated, "the Bearer token is not known to this server");
      if (static_cast<int>(*found->role) < static_cast<int>(route.role)) {
        throw Error(ErrorCode::kForbidden, std::string("this route needs the ") + RoleName(route.role) +
                                               " role; the token has " + RoleName(*found->role));
      }
      caller = *found;
    }
    // Query values reach answers (echoed labels, error messages) and the database as text: they must be UTF-8, as
    // JSON bodies must be (the JSON parser checks those).
    if (req.params.size() > limits::kQueryParameters) {
      throw Error(ErrorCode::kPayloadTooLarge, "more than " + std::to_string(limits::kQueryParameters) + " query parameters", "");
    }
    for (const auto& [key, value] : req.params) {
      limits::CheckLength(key, limits::kQueryValueLength, "query");
      limits::CheckLength(value, limits::kQueryValueLength, key);
      if (!IsUtf8(key)) throw Error(ErrorCode::kInvalidArgument, "a query parameter name is not valid UTF-8");
      if (!IsUtf8(value)) throw Error(ErrorCode::kInvalidArgument, "query parameter is not valid UTF-8", key);
    }
    // After auth and the request's own checks: a refused client hears 401/403/400 first, and takes no slot.
    if (route.write) {
      slot.counter = &writes_in_flight_;
      if (++writes_in_flight_ > options_.max_pending_writes) {
        metrics_.RecordRefusedWrite();
        throw Error(ErrorCode::kOverloaded, "too many writes in flight (" + std::to_string(options_.max_pending_writes) +
                                                "); retry after 1 s");
      }
    }
    std::vector<std::string> values;
    for (std::size_t i = 1; i < req.matches.size(); ++i) {
      values.push_back(req.matches[i].str());
      json::CheckId(values.back(), names[i - 1]);  // the route regex admits the characters; this checks the rest
    }
    const auto call = [&] { return route.handler(req, PathParams(names, values)); };
    Response out = router_.observer() ? router_.observer()(route, caller, RequestContext{req, request_id, names, values}, call)
                                      : call();
    res.status = out.status;
    for (const auto& [k, v] : out.headers) res.set_header(k, v);
    if (out.stream) {
      res.set_chunked_content_provider(out.content_type, [stream = std::move(out.stream)](std::size_t, httplib::DataSink& sink) {
        try {
          return stream(sink);
        } catch (const std::exception&) {
          return false;  // the headers are out: the client sees the stream end and reconnects
        }
      });
    } else {
      res.set_content(std::move(out.body), out.content_type);
    }
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
    options_.log(LogSafe("request_id=" + request_id + " " + req.method + " " + req.path + " status=" +
                         std::to_string(res.status) + buf + log_detail));
  }
}

void HttpApi::Mount(httplib::Server& server) {
  static const std::regex kParam(R"(\{([a-z_]+)\})");
  for (const Route& route : router_.routes()) {
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
    if (options_.log) {
      options_.log(LogSafe(req.method + " " + req.path + " status=" + std::to_string(status) + " error=" + ErrorCodeName(code)));
    }
  });
}

}  // namespace anchordb::api
