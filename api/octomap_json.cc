#include "api/octomap_json.h"

#include "api/request_limits.h"
#include "schema/error.h"

namespace anchordb::api::octomap_json {

namespace {

Eigen::Vector3d AsVector3(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() != 3) throw Error(ErrorCode::kInvalidArgument, field + " must be [x, y, z]", field);
  return {json::AsFiniteNumber(v[0], field), json::AsFiniteNumber(v[1], field), json::AsFiniteNumber(v[2], field)};
}

std::optional<double> OptionalNumber(const Json& body, const char* key) {
  if (!body.contains(key)) return std::nullopt;
  return json::AsFiniteNumber(body.at(key), key);
}

}  // namespace

Json Vector3Json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

services::OctomapConfig ParseConfig(const Json& body) {
  json::RejectUnknownKeys(body, {"resolution_m", "prob_hit", "prob_miss", "clamp_min", "clamp_max",
                                 "occupancy_threshold", "max_range_m"});
  services::OctomapConfig c;
  c.resolution_m = OptionalNumber(body, "resolution_m");
  c.prob_hit = OptionalNumber(body, "prob_hit");
  c.prob_miss = OptionalNumber(body, "prob_miss");
  c.clamp_min = OptionalNumber(body, "clamp_min");
  c.clamp_max = OptionalNumber(body, "clamp_max");
  c.occupancy_threshold = OptionalNumber(body, "occupancy_threshold");
  c.max_range_m = OptionalNumber(body, "max_range_m");
  return c;
}

std::vector<Eigen::Vector3d> ParsePoints(const Json& body, std::size_t max_points) {
  json::RejectUnknownKeys(body, {"points"});
  const Json& points = json::Require(body, "points");
  if (!points.is_array()) throw Error(ErrorCode::kInvalidArgument, "points must be an array of [x, y, z]", "points");
  limits::CheckItems(points, max_points, "points");
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out.push_back(AsVector3(points[i], "points/" + std::to_string(i)));
  return out;
}

services::RayRequest ParseRay(const Json& body) {
  json::RejectUnknownKeys(body, {"origin", "direction", "max_range_m", "ignore_unknown"});
  services::RayRequest r;
  r.origin_map = AsVector3(json::Require(body, "origin"), "origin");
  r.direction_map = AsVector3(json::Require(body, "direction"), "direction");
  r.max_range_m = json::FiniteNumberOr(body, "max_range_m", 10.0);
  r.ignore_unknown = json::BoolOr(body, "ignore_unknown", false);
  return r;
}

engine::Box3 ParseBox(const Json& body, std::initializer_list<std::string_view> extra_keys) {
  std::vector<std::string_view> keys{"min", "max"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  for (const auto& [key, value] : body.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw Error(ErrorCode::kInvalidArgument, "unknown field '" + key + "'", key);
    }
  }
  engine::Box3 box{AsVector3(json::Require(body, "min"), "min"), AsVector3(json::Require(body, "max"), "max")};
  if ((box.min_map.array() > box.max_map.array()).any()) {
    throw Error(ErrorCode::kUnprocessable, "min must not lie above max on any axis", "min");
  }
  return box;
}

namespace {

engine::HeightBand ParseBand(const Json& j, const std::string& path) {
  engine::HeightBand b;
  b.layer = json::RequireId(j, "layer", path);
  b.min_z_m = json::RequireFiniteNumber(j, "min_z_m", path);
  b.max_z_m = json::RequireFiniteNumber(j, "max_z_m", path);
  return b;
}

}  // namespace

services::ProjectRequest ParseProject(const Json& body) {
  services::ProjectRequest r;
  if (body.contains("bands")) {
    json::RejectUnknownKeys(body, {"bands", "like", "resolution_m"});
    const Json& bands = body.at("bands");
    if (!bands.is_array()) throw Error(ErrorCode::kInvalidArgument, "bands must be an array", "bands");
    limits::CheckItems(bands, 16, "bands");
    for (std::size_t i = 0; i < bands.size(); ++i) {
      const std::string path = "bands/" + std::to_string(i);
      if (!bands[i].is_object()) throw Error(ErrorCode::kInvalidArgument, path + " must be an object", path);
      json::RejectUnknownKeys(bands[i], {"layer", "min_z_m", "max_z_m"}, path);
      r.bands.push_back(ParseBand(bands[i], path));
    }
  } else {
    json::RejectUnknownKeys(body, {"layer", "min_z_m", "max_z_m", "like", "resolution_m"});
    r.bands.push_back(ParseBand(body, ""));
  }
  if (body.contains("like")) r.like = json::RequireId(body, "like");
  r.resolution_m = OptionalNumber(body, "resolution_m");
  return r;
}

services::TreeFileFormat ParseTreeFormat(const std::string& format) {
  if (format == "bt") return services::TreeFileFormat::kBt;
  if (format == "ot") return services::TreeFileFormat::kOt;
  throw Error(ErrorCode::kInvalidArgument, "format must be bt or ot", "format");
}

engine::CloudFormat ParseCloudFormat(const std::string& format) {
  if (format == "pcd" || format == "pcd_binary") return engine::CloudFormat::kPcdBinary;
  if (format == "pcd_ascii") return engine::CloudFormat::kPcdAscii;
  if (format == "pcd_binary_compressed") return engine::CloudFormat::kPcdBinaryCompressed;
  if (format == "ply" || format == "ply_binary") return engine::CloudFormat::kPlyBinary;
  if (format == "ply_ascii") return engine::CloudFormat::kPlyAscii;
  throw Error(ErrorCode::kInvalidArgument,
              "format must be pcd, pcd_ascii, pcd_binary, pcd_binary_compressed, ply, ply_ascii or ply_binary", "format");
}

Json ToJson(const services::OctomapInfo& i) {
  const engine::TreeMetadata& m = i.metadata;
  Json bbox = nullptr;
  if (m.min_map && m.max_map) bbox = {{"min", Vector3Json(*m.min_map)}, {"max", Vector3Json(*m.max_map)}};
  return {{"map", i.map},
          {"version", i.version},
          {"resolution_m", i.params.resolution_m},
          {"sensor_model",
           {{"prob_hit", i.params.prob_hit},
            {"prob_miss", i.params.prob_miss},
            {"clamp_min", i.params.clamp_min},
            {"clamp_max", i.params.clamp_max},
            {"occupancy_threshold", i.params.occupancy_threshold}}},
          {"max_range_m", i.max_range_m},
          {"leaves", m.leaves},
          {"occupied_leaves", m.occupied_leaves},
          {"nodes", m.nodes},
          {"memory_bytes", m.memory_bytes},
          {"stored_bytes", i.stored_bytes},
          {"stamped_voxels", m.stamped_voxels},
          {"bbox", bbox},
          {"created_ns", i.created_ns},
          {"updated_ns", i.updated_ns},
          {"keyframes_through", i.keyframes_through},
          {"keyframes_uncommitted", i.keyframes_uncommitted}};
}

Json ToJson(const services::InsertCloudResult& r) {
  return {{"points", r.stats.points},
          {"free_updates", r.stats.free_updates},
          {"occupied_updates", r.stats.occupied_updates},
          {"skipped_nonfinite", r.skipped_nonfinite},
          {"octomap", ToJson(r.octomap)}};
}

Json ToJson(const std::vector<engine::PointOccupancy>& results) {
  Json out = Json::array();
  for (const engine::PointOccupancy& q : results) {
    out.push_back({{"state", engine::VoxelStateName(q.state)},
                   {"probability", q.probability},
                   {"voxel_size_m", q.voxel_size_m},
                   {"stamp_ns", q.stamp_ns ? Json(*q.stamp_ns) : Json(nullptr)}});
  }
  return {{"results", out}};
}

Json ToJson(const engine::RayHit& hit) {
  return {{"hit", hit.stopped_by == engine::VoxelState::kOccupied},
          {"stopped_by", engine::VoxelStateName(hit.stopped_by)},
          {"end", Vector3Json(hit.end_map)},
          {"distance_m", hit.distance_m}};
}

Json ToJson(const services::VoxelsResult& r) {
  Json voxels = Json::array();
  for (const engine::Voxel& v : r.voxels) {
    voxels.push_back({{"center", Vector3Json(v.center_map)},
                      {"size_m", v.size_m},
                      {"log_odds", v.log_odds},
                      {"stamp_ns", v.stamp_ns ? Json(*v.stamp_ns) : Json(nullptr)}});
  }
  return {{"voxels", voxels}, {"count", r.voxels.size()}, {"truncated", r.truncated}};
}

Json ToJson(const services::ProjectResult& r) {
  Json bands = Json::array();
  for (const services::ProjectedBand& b : r.bands) {
    bands.push_back({{"layer", b.layer.name},
                     {"version", b.layer.version},
                     {"min_z_m", b.band.min_z_m},
                     {"max_z_m", b.band.max_z_m},
                     {"cells", {{"occupied", b.cells.occupied}, {"free", b.cells.free}, {"unknown", b.cells.unknown}}}});
  }
  return {{"geometry", json::ToJson(r.geometry)}, {"geometry_from", r.geometry_from}, {"bands", bands}};
}

Json ToJson(const services::ClearBoxResult& r) {
  return {{"voxels_cleared", r.voxels_cleared}, {"octomap", ToJson(r.octomap)}};
}

}  // namespace anchordb::api::octomap_json
