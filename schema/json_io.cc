#include "schema/json_io.h"

#include <cmath>
#include <ctime>

#include "schema/error.h"
#include "schema/unit_quaternion.h"

namespace anchordb::json {
namespace {

std::string Join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

[[noreturn]] void Invalid(const std::string& field, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, field + ": " + what, field);
}

}  // namespace

Json ParseObject(std::string_view text) {
  if (text.empty()) throw Error(ErrorCode::kInvalidJson, "request body is empty; a JSON object is expected");
  Json j;
  try {
    j = Json::parse(text.begin(), text.end());
  } catch (const Json::exception& e) {
    // nlohmann's text names the position and the problem (also "number overflow" for 1e999, which is not finite).
    throw Error(ErrorCode::kInvalidJson, std::string("request body is not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw Error(ErrorCode::kInvalidJson, "request body must be a JSON object");
  return j;
}

void RejectUnknownKeys(const Json& j, std::initializer_list<std::string_view> allowed, const std::string& path) {
  for (const auto& [key, value] : j.items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || a == key;
    if (!known) Invalid(Join(path, key), "unknown field");
  }
}

const Json& Require(const Json& j, const std::string& key, const std::string& path) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) Invalid(Join(path, key), "required field is missing");
  return *it;
}

double AsFiniteNumber(const Json& v, const std::string& field) {
  if (!v.is_number()) Invalid(field, "must be a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) Invalid(field, "must be finite");
  return x;
}

double RequireFiniteNumber(const Json& j, const std::string& key, const std::string& path) {
  return AsFiniteNumber(Require(j, key, path), Join(path, key));
}

double FiniteNumberOr(const Json& j, const std::string& key, double fallback, const std::string& path) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  return AsFiniteNumber(*it, Join(path, key));
}

std::string RequireString(const Json& j, const std::string& key, std::size_t max_length, const std::string& path) {
  const Json& v = Require(j, key, path);
  if (!v.is_string()) Invalid(Join(path, key), "must be a string");
  std::string s = v.get<std::string>();
  if (s.size() > max_length) Invalid(Join(path, key), "longer than " + std::to_string(max_length) + " bytes");
  return s;
}

std::optional<std::string> OptionalString(const Json& j, const std::string& key, std::size_t max_length,
                                          const std::string& path) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  return RequireString(j, key, max_length, path);
}

bool BoolOr(const Json& j, const std::string& key, bool fallback, const std::string& path) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  if (!it->is_boolean()) Invalid(Join(path, key), "must be true or false");
  return it->get<bool>();
}

std::int64_t IntegerOr(const Json& j, const std::string& key, std::int64_t fallback, const std::string& path) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  if (!it->is_number_integer()) Invalid(Join(path, key), "must be an integer");
  return it->get<std::int64_t>();
}

Eigen::Vector2d AsVector2(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() != 2) Invalid(field, "must be an array [x, y]");
  return {AsFiniteNumber(v[0], field + "[0]"), AsFiniteNumber(v[1], field + "[1]")};
}

Pose3 AsPose3(const Json& v, const std::string& field) {
  if (!v.is_object()) Invalid(field, "must be an object {\"position\":[x,y,z],\"orientation\":[qx,qy,qz,qw]}");
  RejectUnknownKeys(v, {"position", "orientation"}, field);
  const Json& p = Require(v, "position", field);
  const Json& q = Require(v, "orientation", field);
  if (!p.is_array() || p.size() != 3) Invalid(field + ".position", "must be an array [x, y, z]");
  if (!q.is_array() || q.size() != 4) Invalid(field + ".orientation", "must be an array [qx, qy, qz, qw]");
  Pose3 pose;
  for (int i = 0; i < 3; ++i) pose.position_m[i] = AsFiniteNumber(p[i], field + ".position[" + std::to_string(i) + "]");
  double c[4];
  for (int i = 0; i < 4; ++i) c[i] = AsFiniteNumber(q[i], field + ".orientation[" + std::to_string(i) + "]");
  const double norm = QuaternionNorm(c[0], c[1], c[2], c[3]);
  if (std::abs(norm - 1.0) > 1e-3) {
    throw Error(ErrorCode::kUnprocessable,
                field + ".orientation: quaternion norm " + std::to_string(norm) + " is not within 1e-3 of 1",
                field + ".orientation");
  }
  pose.orientation = UnitQuaternion(c[0], c[1], c[2], c[3]);
  return pose;
}

Json ToJson(const Pose3& pose) {
  const auto& q = pose.orientation;
  return {{"position", {pose.position_m.x(), pose.position_m.y(), pose.position_m.z()}},
          {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

std::optional<std::int64_t> ParseIso8601Ns(std::string_view text) {
  int Y, M, D, h = 0, m = 0, s = 0, consumed = 0;
  std::string str(text);
  if (std::sscanf(str.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%n", &Y, &M, &D, &h, &m, &s, &consumed) < 6) return std::nullopt;
  if (M < 1 || M > 12 || D < 1 || D > 31 || h > 23 || m > 59 || s > 60) return std::nullopt;
  std::size_t pos = static_cast<std::size_t>(consumed);
  std::int64_t frac_ns = 0;
  if (pos < str.size() && str[pos] == '.') {
    ++pos;
    std::int64_t scale = 100000000;
    std::size_t digits = 0;
    while (pos < str.size() && std::isdigit(static_cast<unsigned char>(str[pos]))) {
      if (digits < 9) frac_ns += (str[pos] - '0') * scale, scale /= 10;
      ++pos, ++digits;
    }
    if (digits == 0) return std::nullopt;
  }
  std::int64_t offset_s = 0;
  if (pos < str.size() && (str[pos] == 'Z' || str[pos] == 'z')) {
    ++pos;
  } else if (pos < str.size() && (str[pos] == '+' || str[pos] == '-')) {
    int oh = 0, om = 0;
    if (std::sscanf(str.c_str() + pos + 1, "%2d:%2d", &oh, &om) != 2) return std::nullopt;
    offset_s = (oh * 3600 + om * 60) * (str[pos] == '+' ? 1 : -1);
    pos += 6;
  } else {
    return std::nullopt;
  }
  if (pos != str.size()) return std::nullopt;
  std::tm tm{};
  tm.tm_year = Y - 1900;
  tm.tm_mon = M - 1;
  tm.tm_mday = D;
  tm.tm_hour = h;
  tm.tm_min = m;
  tm.tm_sec = s;
  const std::int64_t epoch_s = static_cast<std::int64_t>(timegm(&tm)) - offset_s;
  if (epoch_s < 0 || epoch_s >= 9'223'372'036LL) return std::nullopt;  // outside int64 nanoseconds since 1970
  return epoch_s * 1000000000LL + frac_ns;
}

std::int64_t AsStampNs(const Json& v, const std::string& field) {
  if (v.is_number_integer()) {
    const auto ns = v.get<std::int64_t>();
    if (ns < 0) Invalid(field, "must not be negative");
    return ns;
  }
  if (v.is_string()) {
    auto ns = ParseIso8601Ns(v.get<std::string>());
    if (!ns) Invalid(field, "not an ISO 8601 UTC time between 1970 and 2262 such as 2026-11-22T10:00:00Z");
    return *ns;
  }
  Invalid(field, "must be integer nanoseconds since the epoch or an ISO 8601 string");
}

std::vector<Polygon2> AsPolygons(const Json& v, const std::string& field, std::size_t max_polygons,
                                 std::size_t max_vertices) {
  if (!v.is_array()) Invalid(field, "must be an array of polygons [[[x,y],...],...]");
  if (v.size() > max_polygons) {
    throw Error(ErrorCode::kPayloadTooLarge,
                field + ": more than " + std::to_string(max_polygons) + " polygons", field);
  }
  std::vector<Polygon2> polygons;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    if (!v[i].is_array()) Invalid(f, "must be an array of [x,y] vertices");
    if (v[i].size() > max_vertices) {
      throw Error(ErrorCode::kPayloadTooLarge, f + ": more than " + std::to_string(max_vertices) + " vertices", f);
    }
    if (v[i].size() < 3) throw Error(ErrorCode::kUnprocessable, f + ": a polygon needs at least 3 vertices", f);
    Polygon2 polygon;
    for (std::size_t k = 0; k < v[i].size(); ++k) polygon.push_back(AsVector2(v[i][k], f + "[" + std::to_string(k) + "]"));
    polygons.push_back(std::move(polygon));
  }
  return polygons;
}

Json ToJson(const Polygon2& polygon) {
  Json out = Json::array();
  for (const auto& p : polygon) out.push_back({p.x(), p.y()});
  return out;
}

std::string RequireId(const Json& j, const std::string& key, const std::string& path) {
  std::string id = RequireString(j, key, 64, path);
  CheckId(id, Join(path, key));
  return id;
}

Json ToJson(const GridGeometry& g) {
  return {{"width_cells", g.width_cells}, {"height_cells", g.height_cells}, {"resolution_m", g.resolution_m},
          {"origin", {g.origin_x_m, g.origin_y_m, g.origin_yaw_rad}}};
}

Json ToJson(const LogOddsParams& p) {
  return {{"hit", p.hit_probability}, {"miss", p.miss_probability},
          {"clamp_min", p.clamp_min_probability}, {"clamp_max", p.clamp_max_probability}};
}

LogOddsParams AsLogOddsParams(const Json& j, const std::string& path) {
  LogOddsParams p;
  p.hit_probability = FiniteNumberOr(j, "hit", p.hit_probability, path);
  p.miss_probability = FiniteNumberOr(j, "miss", p.miss_probability, path);
  p.clamp_min_probability = FiniteNumberOr(j, "clamp_min", p.clamp_min_probability, path);
  p.clamp_max_probability = FiniteNumberOr(j, "clamp_max", p.clamp_max_probability, path);
  auto in_open_unit = [](double x) { return x > 0.0 && x < 1.0; };
  if (!in_open_unit(p.hit_probability) || p.hit_probability <= 0.5) {
    throw Error(ErrorCode::kUnprocessable, "hit must be in (0.5, 1)", Join(path, "hit"));
  }
  if (!in_open_unit(p.miss_probability) || p.miss_probability >= 0.5) {
    throw Error(ErrorCode::kUnprocessable, "miss must be in (0, 0.5)", Join(path, "miss"));
  }
  if (!in_open_unit(p.clamp_min_probability) || !in_open_unit(p.clamp_max_probability) ||
      p.clamp_min_probability >= 0.5 || p.clamp_max_probability <= 0.5) {
    throw Error(ErrorCode::kUnprocessable, "clamps must satisfy 0 < clamp_min < 0.5 < clamp_max < 1",
                Join(path, "clamp_min"));
  }
  return p;
}

Json ToJson(const Agent& a) {
  return {{"id", a.id},
          {"position", {a.position_m.x(), a.position_m.y()}},
          {"heading_rad", a.heading_rad},
          {"velocity", {a.velocity_mps.x(), a.velocity_mps.y()}},
          {"stamp", a.stamp_ns}};
}

}  // namespace anchordb::json
