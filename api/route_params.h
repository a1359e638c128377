#pragma once
// Parsing of path and query parameters shared by the route files: every failure is a clear Error with the
// parameter's name as the field.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "api/http_api.h"
#include "schema/error.h"
#include "services/grid/grid_types.h"

namespace anchordb::api::params {

inline Response JsonResponse(const Json& j, int status = 200) { return {status, "application/json", j.dump(), {}}; }

// An integer id in the path; anything else names no resource (404).
inline std::int64_t PathId(const PathParams& p, const std::string& name, const std::string& what) {
  const std::string& text = p[name];
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
    throw Error(ErrorCode::kNotFound, what + " '" + text + "' does not exist (ids are integers)", name);
  }
  return std::stoll(text);
}

// An integer query parameter in [lo, hi], or `fallback` when absent.
inline std::int64_t QueryInteger(const httplib::Request& req, const std::string& name, std::int64_t fallback,
                                 std::int64_t lo, std::int64_t hi) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be a non-negative integer", name);
  }
  const std::int64_t v = std::stoll(text);
  if (v < lo || v > hi) {
    throw Error(ErrorCode::kUnprocessable, name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", name);
  }
  return v;
}

// A time query parameter: integer nanoseconds since the epoch or an ISO 8601 string.
inline std::optional<std::int64_t> QueryTime(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return std::nullopt;
  const std::string text = req.get_param_value(name);
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos && text.size() <= 19) return std::stoll(text);
  return json::AsStampNs(Json(text), name);
}

inline std::optional<std::string> QueryString(const httplib::Request& req, const std::string& name, std::size_t max_length) {
  if (!req.has_param(name)) return std::nullopt;
  std::string v = req.get_param_value(name);
  if (v.size() > max_length) throw Error(ErrorCode::kInvalidArgument, name + " is longer than " + std::to_string(max_length) + " characters", name);
  return v;
}

// One of a fixed set of words.
inline std::optional<std::string> QueryChoice(const httplib::Request& req, const std::string& name,
                                              std::initializer_list<const char*> allowed) {
  if (!req.has_param(name)) return std::nullopt;
  const std::string v = req.get_param_value(name);
  std::string list;
  for (const char* a : allowed) {
    if (v == a) return v;
    list += list.empty() ? a : std::string(", ") + a;
  }
  throw Error(ErrorCode::kInvalidArgument, name + " must be one of " + list, name);
}

inline Json BodyObject(const httplib::Request& req) { return req.body.empty() ? Json::object() : json::ParseObject(req.body); }

// A query parameter as given, or nullopt when absent.
inline std::optional<std::string> Query(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

// A finite number ("0.5", "1e-3"), or nullopt when absent; anything else is kInvalidArgument.
inline std::optional<double> OptionalQueryNumber(const httplib::Request& req, const std::string& name) {
  const auto text = Query(req, name);
  if (!text) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text->c_str(), &end);
  if (text->empty() || end != text->c_str() + text->size() || !std::isfinite(v)) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be a finite number", name);
  }
  return v;
}

// A finite number in [lo, hi] (kUnprocessable outside), or `fallback` (unchecked) when absent.
inline double QueryNumber(const httplib::Request& req, const std::string& name, double fallback, double lo, double hi) {
  const auto given = OptionalQueryNumber(req, name);
  if (!given) return fallback;
  const double v = *given;
  if (v < lo || v > hi) {
    throw Error(ErrorCode::kUnprocessable, name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", name);
  }
  return v;
}

// A whole number written as any number ("10", "1e1"; "2.5" is kInvalidArgument) in [lo, hi], or `fallback` when
// absent. (QueryInteger accepts digits only.)
inline int QueryWholeNumber(const httplib::Request& req, const std::string& name, int fallback, int lo, int hi) {
  const double v = QueryNumber(req, name, fallback, lo, hi);
  if (v != std::floor(v)) throw Error(ErrorCode::kInvalidArgument, name + " must be an integer", name);
  return static_cast<int>(v);
}

// "true" or "false" (kInvalidArgument otherwise), or `fallback` when absent.
inline bool QueryTrueFalse(const httplib::Request& req, const std::string& name, bool fallback) {
  const auto v = Query(req, name);
  if (!v) return fallback;
  if (*v != "true" && *v != "false") throw Error(ErrorCode::kInvalidArgument, name + " must be true or false", name);
  return *v == "true";
}

// An id (json::CheckId) that must be given.
inline std::string RequireQueryId(const httplib::Request& req, const std::string& name) {
  const auto v = Query(req, name);
  if (!v) throw Error(ErrorCode::kInvalidArgument, "query parameter '" + name + "' is required", name);
  json::CheckId(*v, name);
  return *v;
}

// A box `name`=min_x,min_y,max_x,max_y [m] in the map frame, or nullopt when absent.
inline std::optional<services::Bbox> QueryBbox(const httplib::Request& req, const std::string& name = "bbox") {
  const auto text = Query(req, name);
  if (!text) return std::nullopt;
  double v[4];
  char tail = 0;
  if (std::sscanf(text->c_str(), "%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &tail) != 4 ||
      !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be min_x,min_y,max_x,max_y in metres", name);
  }
  if (v[0] > v[2] || v[1] > v[3]) throw Error(ErrorCode::kUnprocessable, name + " minimum exceeds its maximum", name);
  return services::Bbox{v[0], v[1], v[2], v[3]};
}

// true | 1 | false | 0; false when absent.
inline bool QueryBool(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return false;
  const std::string v = req.get_param_value(name);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  throw Error(ErrorCode::kInvalidArgument, name + " must be true or false", name);
}

// A point "x,y,z" [m] of finite numbers, or nullopt when absent.
inline std::optional<Eigen::Vector3d> QueryPoint3(const httplib::Request& req, const std::string& name) {
  if (!req.has_param(name)) return std::nullopt;
  double v[3];
  char tail = 0;
  if (std::sscanf(req.get_param_value(name).c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3 ||
      !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw Error(ErrorCode::kInvalidArgument, name + " must be x,y,z in metres", name);
  }
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

}  // namespace anchordb::api::params
