#include "api/grid_json.h"
#include "api/layer_meta_json.h"
#include "api/request_limits.h"

#include <cmath>
#include <cstdlib>

#include "schema/error.h"

namespace anchordb::api::grid_json {

using namespace anchordb::services;

namespace {

// ---------------------------------------------------------------- layer specs, one parser per kind

LayerSpec ParseProbabilitySpec(const Json& body, const std::string&) {
  json::RejectUnknownKeys(body, {"kind", "base", "log_odds"});
  ProbabilityLayerSpec spec;
  spec.base = json::RequireId(body, "base");
  if (body.contains("log_odds")) {
    if (!body["log_odds"].is_object()) throw Error(ErrorCode::kInvalidArgument, "log_odds must be an object", "log_odds");
    json::RejectUnknownKeys(body["log_odds"], {"hit", "miss", "clamp_min", "clamp_max"}, "log_odds");
    spec.log_odds = json::AsLogOddsParams(body["log_odds"], "log_odds");
  }
  return spec;
}

LayerSpec ParseLabelSpec(const Json& body, const std::string&) {
  json::RejectUnknownKeys(body, {"kind", "base", "labels"});
  LabelLayerSpec spec;
  spec.base = json::RequireId(body, "base");
  if (body.contains("labels")) {
    if (!body["labels"].is_object()) {
      throw Error(ErrorCode::kInvalidArgument, "labels must be an object {\"1\":\"kitchen\"}", "labels");
    }
    for (const auto& [id, name] : body["labels"].items()) {
      const int n = std::atoi(id.c_str());
      if (n < 1 || n > 65535 || std::to_string(n) != id || !name.is_string()) {
        throw Error(ErrorCode::kInvalidArgument, "labels: keys are ids 1-65535, values names", "labels." + id);
      }
      spec.labels[n] = name.get<std::string>();
      limits::CheckLength(spec.labels[n], limits::kLabelLength, "labels." + id);
    }
  }
  return spec;
}

FuseOperand ParseOperand(const Json& operand, const std::string& path, const std::string& layer) {
  if (!operand.is_object()) throw Error(ErrorCode::kInvalidArgument, path + " must be an object", path);
  json::RejectUnknownKeys(operand, {"layer", "threshold"}, path);
  FuseOperand out;
  out.layer = json::RequireId(operand, "layer", path);
  out.threshold = json::FiniteNumberOr(operand, "threshold", 0.5, path);
  if (out.threshold < 0.0 || out.threshold > 1.0) {
    throw Error(ErrorCode::kUnprocessable, path + ".threshold must be in [0, 1]", path + ".threshold");
  }
  if (out.layer == layer) throw Error(ErrorCode::kUnprocessable, "a fused layer cannot use itself", path + ".layer");
  return out;
}

LayerSpec ParseFusedSpec(const Json& body, const std::string& layer) {
  json::RejectUnknownKeys(body, {"kind", "op", "operands"});
  const std::string op = json::RequireString(body, "op", limits::kWordLength);
  FusedLayerSpec spec;
  bool known = false;
  for (FuseOp candidate : {FuseOp::kAnd, FuseOp::kOr, FuseOp::kAndNot, FuseOp::kXor}) {
    if (op == FuseOpName(candidate)) spec.op = candidate, known = true;
  }
  if (!known) throw Error(ErrorCode::kInvalidArgument, "op must be and, or, and_not or xor", "op");
  const Json& operands = json::Require(body, "operands");
  if (!operands.is_array() || operands.size() < 2 || operands.size() > limits::kFusedOperands) {
    throw Error(ErrorCode::kInvalidArgument, "operands must be an array of 2-16 {\"layer\",\"threshold\"}", "operands");
  }
  for (std::size_t i = 0; i < operands.size(); ++i) {
    spec.operands.push_back(ParseOperand(operands[i], "operands[" + std::to_string(i) + "]", layer));
  }
  return spec;
}

struct SpecParser {
  LayerKind kind;
  LayerSpec (*parse)(const Json& body, const std::string& layer);
};

// The kinds a client creates from JSON, in the order the error message lists them.
constexpr SpecParser kSpecParsers[] = {{ProbabilityLayerSpec::kKind, ParseProbabilitySpec},
                                       {FusedLayerSpec::kKind, ParseFusedSpec},
                                       {LabelLayerSpec::kKind, ParseLabelSpec}};

// ---------------------------------------------------------------- result pieces

Json RegionJson(const engine::Region& r) {
  return {{"id", r.id},
          {"area_m2", r.area_m2},
          {"cells", r.cell_count},
          {"centroid", {r.centroid_m.x(), r.centroid_m.y()}},
          {"mean_probability", r.mean_probability},
          {"polygon", json::ToJson(r.polygon_m)}};
}

Json RelationJson(const engine::RegionRelation& r) {
  return {{"region", r.region_id},       {"distance_m", r.distance_m}, {"facing_angle_rad", r.facing_angle_rad},
          {"nearest", {r.nearest_m.x(), r.nearest_m.y()}}, {"near", r.near}, {"facing", r.facing}};
}

Json StatisticsJson(const engine::OccupancyStatistics& s) {
  return {{"occupied_cells", s.occupied_cells}, {"free_cells", s.free_cells}, {"unknown_cells", s.unknown_cells}};
}

Json StatisticsJson(const engine::LabelStatistics& s) {
  Json per = Json::object();
  for (const auto& [id, n] : s.cells_per_label) per[std::to_string(id)] = n;
  return {{"cells_per_label", per}};
}

Json StatisticsJson(const engine::ProbabilityStatistics& s) {
  return {{"min_probability", s.min_probability}, {"max_probability", s.max_probability},
          {"mean_probability", s.mean_probability}, {"cells_above_0_5", s.cells_above_half}};
}

}  // namespace

// ---------------------------------------------------------------- requests

CreateMapRequest ParseCreateMap(const Json& body) {
  json::RejectUnknownKeys(body, {"id", "name"});
  CreateMapRequest request;
  request.id = json::RequireId(body, "id");
  request.name = json::OptionalString(body, "name", limits::kNameLength).value_or(request.id);
  return request;
}

LayerSpec ParseLayerSpec(const Json& body, const std::string& layer) {
  const std::string kind = json::RequireString(body, "kind", limits::kWordLength);
  std::string names;
  for (const SpecParser& p : kSpecParsers) {
    if (kind == LayerKindName(p.kind)) return p.parse(body, layer);
    const bool last = &p == &kSpecParsers[std::size(kSpecParsers) - 1];
    names += (names.empty() ? "" : last ? " or " : ", ") + std::string(LayerKindName(p.kind));
  }
  throw Error(ErrorCode::kInvalidArgument,
              "kind must be " + names + " (occupancy layers are imported as multipart yaml + image)", "kind");
}

LayerFormat ParseLayerFormat(const std::string& format) {
  if (format == "png") return LayerFormat::kPng;
  if (format == "pgm") return LayerFormat::kPgm;
  if (format == "yaml") return LayerFormat::kYaml;
  if (format == "raw") return LayerFormat::kRaw;
  throw Error(ErrorCode::kInvalidArgument, "format must be json, png, pgm, yaml or raw", "format");
}

engine::Observation ParseObservation(const Json& body, const ServiceLimits& limits) {
  json::RejectUnknownKeys(body, {"pose", "fov_rad", "range_m", "stimulus", "stamp"});
  engine::Observation obs;
  const Pose3 pose = json::AsPose3(json::Require(body, "pose"), "pose");
  obs.sensor_position_m = pose.position_m.head<2>();
  obs.heading_rad = pose.YawRad();
  obs.fov_rad = json::RequireFiniteNumber(body, "fov_rad");
  obs.range_m = json::RequireFiniteNumber(body, "range_m");
  if (obs.fov_rad <= 0.0 || obs.fov_rad > 2.0 * M_PI + 1e-9) {
    throw Error(ErrorCode::kUnprocessable, "fov_rad must be in (0, 2*pi]", "fov_rad");
  }
  if (obs.range_m <= 0.0 || obs.range_m > 100.0) throw Error(ErrorCode::kUnprocessable, "range_m must be in (0, 100]", "range_m");
  if (body.contains("stamp")) json::AsStampNs(body["stamp"], "stamp");
  obs.stimulus_map = json::AsPolygons(json::Require(body, "stimulus"), "stimulus", limits.max_polygons, limits.max_polygon_vertices);
  return obs;
}

PaintLabelRequest ParsePaintLabel(const Json& body, const ServiceLimits& limits) {
  json::RejectUnknownKeys(body, {"label", "polygons"});
  PaintLabelRequest request;
  request.label = json::RequireString(body, "label", limits::kLabelLength);
  if (request.label.empty()) throw Error(ErrorCode::kInvalidArgument, "label must not be empty", "label");
  request.polygons_map =
      json::AsPolygons(json::Require(body, "polygons"), "polygons", limits.max_polygons, limits.max_polygon_vertices);
  return request;
}

PutAgentRequest ParsePutAgent(const Json& body) {
  json::RejectUnknownKeys(body, {"position", "heading_rad", "velocity", "stamp"});
  PutAgentRequest request;
  Agent& a = request.agent;
  a.position_m = json::AsVector2(json::Require(body, "position"), "position");
  a.heading_rad = std::remainder(json::RequireFiniteNumber(body, "heading_rad"), 2.0 * M_PI);
  if (body.contains("velocity")) a.velocity_mps = json::AsVector2(body["velocity"], "velocity");
  if (body.contains("stamp")) request.stamp_ns = json::AsStampNs(body["stamp"], "stamp");
  return request;
}

ViewpointsRequest ParseViewpoints(const Json& body) {
  json::RejectUnknownKeys(body, {"robot", "agent", "layer", "threshold", "region", "max"});
  ViewpointsRequest request;
  request.robot_m = json::AsVector2(json::Require(body, "robot"), "robot");
  request.agent = json::RequireId(body, "agent");
  request.layer = json::RequireId(body, "layer");
  request.threshold = json::FiniteNumberOr(body, "threshold", 0.5);
  if (request.threshold < 0.0 || request.threshold > 1.0) {
    throw Error(ErrorCode::kUnprocessable, "threshold must be in [0, 1]", "threshold");
  }
  if (body.contains("region")) request.region = static_cast<int>(json::IntegerOr(body, "region", 0));
  const auto max = json::IntegerOr(body, "max", 10);
  if (max < 1 || max > 100) throw Error(ErrorCode::kUnprocessable, "max must be in [1, 100]", "max");
  request.max_viewpoints = static_cast<int>(max);
  return request;
}

// ---------------------------------------------------------------- results

Json ToJson(const MapInfo& m) { return {{"id", m.id}, {"name", m.name}, {"created_ns", m.created_ns}}; }

Json ToJson(const MapPage& page) {
  Json out = {{"maps", Json::array()}, {"next_cursor", nullptr}};
  for (const MapInfo& m : page.maps) out["maps"].push_back(ToJson(m));
  if (page.next_cursor) out["next_cursor"] = *page.next_cursor;
  return out;
}

Json ToJson(const MapDetails& details) {
  Json out = ToJson(details.map);
  out["layers"] = Json::array();
  for (const LayerSummary& l : details.layers) {
    out["layers"].push_back({{"name", l.name}, {"kind", LayerKindName(l.kind)}});
  }
  out["agents"] = details.agents;
  return out;
}

Json ToJson(const LayerInfo& l) {
  Json out = {{"map", l.map},           {"name", l.name},             {"kind", LayerKindName(l.kind)},
              {"version", l.version},   {"created_ns", l.created_ns}, {"updated_ns", l.updated_ns},
              {"stored_bytes", l.stored_bytes}};
  // The metadata (api/layer_meta_json.h), key by key.
  const Json meta = LayerMetaJson(l.meta);
  for (const auto& [key, value] : meta.items()) out[key] = value;
  if (l.statistics) out["statistics"] = std::visit([](const auto& s) { return StatisticsJson(s); }, *l.statistics);
  return out;
}

Json ToJson(const std::vector<LayerInfo>& layers) {
  Json out = {{"layers", Json::array()}};
  for (const LayerInfo& l : layers) out["layers"].push_back(ToJson(l));
  return out;
}

Json ToJson(const ObservationResult& r) {
  return {{"layer", r.layer}, {"version", r.version}, {"cells_raised", r.counts.raised},
          {"cells_lowered", r.counts.lowered}, {"cells_unchanged_blocked", r.counts.unchanged_blocked},
          {"stimulus_cells_outside_view", r.counts.stimulus_outside_view}};
}

Json ToJson(const PaintLabelResult& r) {
  return {{"layer", r.layer}, {"version", r.version}, {"label", r.label}, {"label_id", r.label_id}, {"cells", r.cells}};
}

Json ToJson(const LayerRegions& r) {
  Json out = {{"layer", r.layer}, {"version", r.version}, {"threshold", r.threshold}, {"regions", Json::array()}};
  for (const engine::Region& region : r.regions) out["regions"].push_back(RegionJson(region));
  return out;
}

Json ToJson(const std::vector<Agent>& agents) {
  Json out = {{"agents", Json::array()}};
  for (const Agent& a : agents) out["agents"].push_back(json::ToJson(a));
  return out;
}

Json ToJson(const AttentionResult& r) {
  Json out = {{"agent", r.agent}, {"layer", r.layer}, {"attending", r.attention.attending}, {"region", nullptr},
              {"relations", Json::array()}};
  for (const auto& rel : r.attention.relations) out["relations"].push_back(RelationJson(rel));
  if (r.attention.attended) {
    if (r.region) out["region"] = RegionJson(*r.region);
    out["distance_m"] = r.attention.attended->distance_m;
    out["facing_angle_rad"] = r.attention.attended->facing_angle_rad;
  }
  return out;
}

Json ToJson(const ViewpointsResult& r) {
  Json out = {{"agent", r.agent}, {"layer", r.layer}, {"region", RegionJson(r.region)},
              {"boundary_cells", r.plan.boundary_cells}, {"candidate_cells", r.plan.candidate_cells},
              {"clusters", r.plan.clusters}, {"viewpoints", Json::array()}};
  out["region"].erase("polygon");
  int rank = 1;
  for (const auto& v : r.plan.viewpoints) {
    out["viewpoints"].push_back({{"rank", rank++}, {"position", {v.position_m.x(), v.position_m.y()}}, {"yaw_rad", v.yaw_rad},
                                 {"score", v.score}, {"position_score", v.position_score}, {"travel_score", v.travel_score},
                                 {"travel_distance_m", v.travel_distance_m}, {"surface_distance_m", v.surface_distance_m},
                                 {"person_distance_m", v.person_distance_m}, {"relative_angle_rad", v.relative_angle_rad},
                                 {"relation", v.relation}});
  }
  return out;
}

}  // namespace anchordb::api::grid_json
