#pragma once
// JSON of the octomap routes: request bodies -> typed OctomapService requests (strict: unknown keys, wrong types,
// non-finite numbers are Error kInvalidArgument naming the field), typed results -> the documents clients see.
#include <string>
#include <vector>

#include "schema/json_io.h"
#include "services/octomap/octomap_service.h"

namespace anchordb::api::octomap_json {

using json::Json;

services::OctomapConfig ParseConfig(const Json& body);
// {"points":[[x,y,z],...]} with at most `max_points` points (413 beyond).
std::vector<Eigen::Vector3d> ParsePoints(const Json& body, std::size_t max_points);
services::RayRequest ParseRay(const Json& body);
// {"min":[x,y,z],"max":[x,y,z]} (and, for listings, "limit")
engine::Box3 ParseBox(const Json& body, std::initializer_list<std::string_view> extra_keys = {});
// {"layer","min_z_m","max_z_m"} or {"bands":[{"layer","min_z_m","max_z_m"},...]}, with optional "like", "resolution_m".
services::ProjectRequest ParseProject(const Json& body);
services::TreeFileFormat ParseTreeFormat(const std::string& format);
engine::CloudFormat ParseCloudFormat(const std::string& format);

Json ToJson(const services::OctomapInfo& info);
Json ToJson(const services::InsertCloudResult& result);
Json ToJson(const std::vector<engine::PointOccupancy>& results);
Json ToJson(const engine::RayHit& hit);
Json ToJson(const services::VoxelsResult& voxels);
Json ToJson(const services::ClearBoxResult& result);
Json ToJson(const services::ProjectResult& result);
Json Vector3Json(const Eigen::Vector3d& v);

}  // namespace anchordb::api::octomap_json
