// The grid functions about people: tracked persons (agents), the attention query, and ranked observation viewpoints
// around the attended surface.
#include "services/grid/grid_service.h"

#include "services/grid/grid_service_internal.h"
#include "schema/error.h"

namespace anchordb::services {

using namespace detail;       // NOLINT: the codec helpers are this file's vocabulary
using namespace grid_detail;  // NOLINT

namespace {

Json RelationJson(const engine::RegionRelation& r) {
  return {{"region", r.region_id},       {"distance_m", r.distance_m}, {"facing_angle_rad", r.facing_angle_rad},
          {"nearest", {r.nearest_m.x(), r.nearest_m.y()}}, {"near", r.near}, {"facing", r.facing}};
}

}  // namespace

Json GridService::PutAgent(const std::string& map, const Agent& agent) {
  store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::UpsertAgent(c, map, agent);
  });
  return json::ToJson(agent);
}

Json GridService::GetAgent(const std::string& map, const std::string& id) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto agent = storage::FindAgent(c, map, id);
    if (!agent) throw Error(ErrorCode::kNotFound, "agent '" + id + "' does not exist in map '" + map + "'", "agent");
    return json::ToJson(*agent);
  });
}

Json GridService::ListAgents(const std::string& map, const std::optional<storage::Bbox>& bbox) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    Json out = {{"agents", Json::array()}};
    for (const auto& a : storage::ListAgents(c, map, bbox)) out["agents"].push_back(json::ToJson(a));
    return out;
  });
}

Json GridService::Attention(const std::string& map, const std::string& agent_id, const std::string& layer, double threshold) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto agent = storage::FindAgent(c, map, agent_id);
    if (!agent) throw Error(ErrorCode::kNotFound, "agent '" + agent_id + "' does not exist in map '" + map + "'", "agent");
    const storage::LayerRecord record = RequireLayer(c, map, layer);
    const engine::ProbabilityGrid p = EvaluateProbability(c, record);
    const auto regions = engine::ExtractRegions(p, threshold, 0.0);
    const auto result = engine::ComputeAttention(*agent, regions, p.geometry, defaults_.attention);
    Json out = {{"agent", agent_id}, {"layer", layer}, {"attending", result.attending}, {"region", nullptr},
                {"relations", Json::array()}};
    for (const auto& rel : result.relations) out["relations"].push_back(RelationJson(rel));
    if (result.attended) {
      for (const auto& r : regions) {
        if (r.id == result.attended->region_id) out["region"] = RegionJson(r);
      }
      out["distance_m"] = result.attended->distance_m;
      out["facing_angle_rad"] = result.attended->facing_angle_rad;
    }
    return out;
  });
}

Json GridService::Viewpoints(const std::string& map, const Eigen::Vector2d& robot_m, const std::string& agent_id,
                             const std::string& layer, double threshold, std::optional<int> region_id, int max_viewpoints) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto agent = storage::FindAgent(c, map, agent_id);
    if (!agent) throw Error(ErrorCode::kNotFound, "agent '" + agent_id + "' does not exist in map '" + map + "'", "agent");
    const storage::LayerRecord record = RequireLayer(c, map, layer);
    const Json meta = ParseMeta(record);
    std::string base_name;
    if (meta.contains("base")) base_name = meta["base"].get<std::string>();
    else if (record.kind == LayerKind::kOccupancy) base_name = layer;
    else {
      // A fused layer: the base of its first operand.
      const auto first = RequireLayer(c, map, meta.at("operands")[0].at("layer").get<std::string>());
      base_name = ParseMeta(first).value("base", first.name);
    }
    const OccupancyLayer occupancy = DecodeOccupancy(RequireOccupancyBase(c, map, base_name));
    const engine::ProbabilityGrid p = EvaluateProbability(c, record);
    const auto regions = engine::ExtractRegions(p, threshold, 0.0);
    if (regions.empty()) throw Error(ErrorCode::kUnprocessable, "layer '" + layer + "' has no region above the threshold", "layer");
    // Which surface: the one asked for, else the one the person attends to, else the nearest to the person.
    int chosen = 0;
    if (region_id) {
      chosen = *region_id;
      if (chosen < 1 || chosen > static_cast<int>(regions.size())) {
        throw Error(ErrorCode::kNotFound, "region " + std::to_string(chosen) + " does not exist", "region");
      }
    } else {
      const auto attention = engine::ComputeAttention(*agent, regions, p.geometry, defaults_.attention);
      chosen = attention.attended ? attention.attended->region_id : attention.relations.front().region_id;
    }
    const engine::Region& region = regions[chosen - 1];
    engine::MaskGrid surface(p.geometry, 0);
    for (int cell : region.cells) surface.cells[cell] = 1;
    engine::ViewpointOptions options = defaults_.viewpoints;
    options.occupancy = defaults_.occupancy;
    options.max_viewpoints = max_viewpoints;
    const auto plan = engine::PlanViewpoints(occupancy.grid, surface, robot_m, *agent, options);
    Json out = {{"agent", agent_id}, {"layer", layer}, {"region", RegionJson(region)},
                {"boundary_cells", plan.boundary_cells}, {"candidate_cells", plan.candidate_cells},
                {"clusters", plan.clusters}, {"viewpoints", Json::array()}};
    out["region"].erase("polygon");
    int rank = 1;
    for (const auto& v : plan.viewpoints) {
      out["viewpoints"].push_back({{"rank", rank++}, {"position", {v.position_m.x(), v.position_m.y()}}, {"yaw_rad", v.yaw_rad},
                                   {"score", v.score}, {"position_score", v.position_score}, {"travel_score", v.travel_score},
                                   {"travel_distance_m", v.travel_distance_m}, {"surface_distance_m", v.surface_distance_m},
                                   {"person_distance_m", v.person_distance_m}, {"relative_angle_rad", v.relative_angle_rad},
                                   {"relation", v.relation}});
    }
    return out;
  });
}

}  // namespace anchordb::services
