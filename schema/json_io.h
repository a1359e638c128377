#pragma once
// Strict JSON readers for request bodies and writers for responses. Every reader throws anchordb::Error
// with the offending field's path: kInvalidJson for unparsable text, kInvalidArgument for a missing field, a
// wrong type, a non-finite number, an unknown key or an over-long array, kUnprocessable for values that
// parse but cannot be (a non-unit quaternion, a negative range).
#include <nlohmann/json.hpp>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "schema/ids.h"
#include "schema/types.h"

namespace anchordb::json {

using Json = nlohmann::json;

// Parses a request body; an empty or malformed text is kInvalidJson. The top level must be an object.
Json ParseObject(std::string_view text);

// Fails with kInvalidArgument if `j` has a key not in `allowed`.
void RejectUnknownKeys(const Json& j, std::initializer_list<std::string_view> allowed, const std::string& path = {});

const Json& Require(const Json& j, const std::string& key, const std::string& path = {});
double RequireFiniteNumber(const Json& j, const std::string& key, const std::string& path = {});
double FiniteNumberOr(const Json& j, const std::string& key, double fallback, const std::string& path = {});
std::string RequireString(const Json& j, const std::string& key, std::size_t max_length,
                          const std::string& path = {});
std::optional<std::string> OptionalString(const Json& j, const std::string& key, std::size_t max_length,
                                          const std::string& path = {});
bool BoolOr(const Json& j, const std::string& key, bool fallback, const std::string& path = {});
std::int64_t IntegerOr(const Json& j, const std::string& key, std::int64_t fallback, const std::string& path = {});

// A JSON number (checked finite) as a double; `field` names it in errors.
double AsFiniteNumber(const Json& v, const std::string& field);
// [x, y] with finite numbers.
Eigen::Vector2d AsVector2(const Json& v, const std::string& field);
// {"position":[x,y,z],"orientation":[qx,qy,qz,qw]}; the quaternion must be within 1e-3 of unit norm
// (then it is normalised), otherwise kUnprocessable.
Pose3 AsPose3(const Json& v, const std::string& field);
Json ToJson(const Pose3& pose);
// Integer nanoseconds since the epoch, or an ISO 8601 UTC string ("2026-11-22T10:00:00.5Z").
std::int64_t AsStampNs(const Json& v, const std::string& field);
// Parses ISO 8601 (UTC, 'Z' or +hh:mm offset); nullopt when malformed.
std::optional<std::int64_t> ParseIso8601Ns(std::string_view text);
// A list of polygons [[[x,y],...],...], each with 3..max_vertices vertices, at most max_polygons.
std::vector<Polygon2> AsPolygons(const Json& v, const std::string& field, std::size_t max_polygons,
                                 std::size_t max_vertices);
Json ToJson(const Polygon2& polygon);

// An identifier read from a body: a string that IsValidId (schema/ids.h).
std::string RequireId(const Json& j, const std::string& key, const std::string& path = {});

Json ToJson(const GridGeometry& geometry);
Json ToJson(const LogOddsParams& params);
LogOddsParams AsLogOddsParams(const Json& j, const std::string& path);
Json ToJson(const Agent& agent);

}  // namespace anchordb::json
