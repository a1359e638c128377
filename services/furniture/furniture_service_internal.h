#pragma once
// Internal to services/furniture/*.cc: the in-memory state of a furniture graph, the checks of typed requests
// (furniture_requests.cc) and the mapping of a graph to its stored records (furniture_graph_records.cc).
#include <mutex>
#include <string>
#include <vector>

#include "engine/grid/grid.h"
#include "services/furniture/furniture_service.h"
#include "schema/error.h"

namespace anchordb::services {

namespace g = engine::grounding;

namespace furniture_detail {

// Requests (furniture_requests.cc). Each check throws Error naming the offending field.
FurnitureGraphParams ResolveParams(const GraphParamsRequest& request, const FurnitureSettings& settings);
g::GroundingParams GroundingParamsOf(const FurnitureGraphParams& params);
std::vector<g::FurnitureInput> ResolveFurniture(const std::vector<FurniturePieceRequest>& pieces,
                                                const g::CategoryTable& table, int max_furniture);
// The description in the graph's categories, and what it was understood as.
struct ResolvedDescription {
  g::Description description;
  Understood understood;
};
ResolvedDescription ResolveDescription(const DescriptionRequest& request, const g::CategoryTable& table);

// The occupancy layer a graph's room prior uses when the request names none: the map's occupancy layer named
// "occupancy", else its only occupancy layer; "" when it has none (or several, none of them named so).
std::string DefaultOccupancyLayer(storage::Store& store, const std::string& map);
// The occupancy grid of layer `layer` of `map` for the room's orientation prior; nullopt when `layer` is empty.
// Unknown layer kNotFound, a layer of another kind kUnprocessable (furniture_room.cc).
std::optional<engine::OccupancyGrid> OccupancyOf(storage::Store& store, const std::string& map, const std::string& layer);

// The vertex with id `id` (a pair's `field`, "located" or "reference"); kNotFound naming the field otherwise.
int VertexOrNotFound(const g::FurnitureGraph& graph, const std::string& id, const char* field);

// A match of the engine in the terms a client is told (furniture_service.cc).
MatchView MatchOf(const g::FurnitureGraph& graph, const g::Match& m);

// The stored form (furniture_graph_records.cc): the graph as built is stored whole, so that a later change of the
// building code cannot change a live conversation. A record the database holds that does not fit (a vertex's p(f)
// of another length, an edge to no vertex) is kInternal naming the graph.
void StoreGraph(storage::FurnitureGraphRecord& record, const g::Viewpoint& viewpoint, const FurnitureGraphParams& params,
                const g::FurnitureGraph& graph);
g::Viewpoint ViewpointOf(const storage::FurnitureGraphRecord& record);
FurnitureGraphParams ParamsOf(const storage::FurnitureGraphParamsRecord& record);
g::FurnitureGraph GraphOf(const storage::FurnitureGraphRecord& record);
// A description as given (the input stored with it).
void StoreInput(storage::GraphDescriptionRecord& record, const DescriptionRequest& request);
DescriptionRequest InputOf(const storage::GraphDescriptionRecord& record);

}  // namespace furniture_detail

struct FurnitureService::Graph {
  std::mutex mutex;
  storage::FurnitureGraphRecord record;  // hypotheses blob not kept here
  g::FurnitureGraph graph;
  g::Knowledge knowledge;
  FurnitureGraphParams params;
  g::Viewpoint viewpoint;
  g::HypothesisSet set;
};

namespace furniture_detail {
// The competing readings of description `step` and the question to ask back (furniture_ambiguity.cc).
AmbiguityView AmbiguityOf(const FurnitureService::Graph& graph, int step, const g::Description& d, bool ambiguous, bool poor);
// The pending (held) descriptions of the graph's live set.
std::vector<AmbiguityView> PendingOf(const FurnitureService::Graph& graph);
}  // namespace furniture_detail

}  // namespace anchordb::services
