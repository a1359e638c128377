// The grid functions about people: tracked persons (agents), the attention query, and ranked observation viewpoints
// around the attended surface.
#include "services/grid/grid_service.h"

#include "schema/error.h"
#include "services/grid/grid_service_internal.h"

namespace anchordb::services {

using grid_detail::MapLayers;
using grid_detail::RequireAgent;

Agent GridService::PutAgent(const PutAgentRequest& request) {
  Agent agent = request.agent;
  agent.stamp_ns = request.stamp_ns.value_or(clock_.NowNs());
  store_.Write([&](storage::Connection& c) {
    grid_detail::RequireMap(c, request.map);
    storage::UpsertAgent(c, request.map, agent);
  });
  return agent;
}

Agent GridService::GetAgent(const std::string& map, const std::string& agent) {
  return store_.Read([&](storage::Connection& c) {
    grid_detail::RequireMap(c, map);
    return RequireAgent(c, map, agent);
  });
}

std::vector<Agent> GridService::ListAgents(const std::string& map, const std::optional<storage::Bbox>& bbox_map) {
  return store_.Read([&](storage::Connection& c) {
    grid_detail::RequireMap(c, map);
    return storage::ListAgents(c, map, bbox_map);
  });
}

AttentionResult GridService::Attention(const AttentionRequest& request) {
  return store_.Read([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    const Agent agent = RequireAgent(c, request.map, request.agent);
    const engine::ProbabilityGrid p = layers.Probability(layers.Require(request.layer));
    auto regions = engine::ExtractRegions(p, request.threshold, 0.0);
    AttentionResult out{request.agent, request.layer,
                        engine::ComputeAttention(agent, regions, p.geometry, defaults_.attention), {}};
    if (out.attention.attended) {
      for (auto& r : regions) {
        if (r.id == out.attention.attended->region_id) out.region = std::move(r);
      }
    }
    return out;
  });
}

ViewpointsResult GridService::Viewpoints(const ViewpointsRequest& request) {
  return store_.Read([&](storage::Connection& c) {
    const MapLayers layers(c, request.map);
    const Agent agent = RequireAgent(c, request.map, request.agent);
    const storage::LayerRecord record = layers.Require(request.layer);
    const grid_detail::OccupancyView occupancy =
        grid_detail::DecodeOccupancyView(layers.RequireOccupancy(layers.OccupancyBase(record)));
    const engine::ProbabilityGrid p = layers.Probability(record);
    auto regions = engine::ExtractRegions(p, request.threshold, 0.0);
    if (regions.empty()) {
      throw Error(ErrorCode::kUnprocessable, "layer '" + request.layer + "' has no region above the threshold", "layer");
    }
    const int chosen = engine::ChooseSurfaceRegion(regions, p.geometry, agent, defaults_.attention, request.region);
    engine::Region& region = regions[chosen - 1];
    engine::ViewpointOptions options = defaults_.viewpoints;
    options.occupancy = defaults_.occupancy;
    options.max_viewpoints = request.max_viewpoints;
    engine::ViewpointPlan plan =
        engine::PlanViewpoints(occupancy.grid, engine::RegionMask(region, p.geometry), request.robot_m, agent, options);
    return ViewpointsResult{request.agent, request.layer, std::move(region), std::move(plan)};
  });
}

}  // namespace anchordb::services
