#pragma once
// Internal to services/furniture/*.cc: the in-memory state of a furniture graph, the checks of typed requests
// (furniture_requests.cc) and the stored form of a graph (furniture_graph_json.cc: JSON documents in the database).
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

// The stored form (furniture_graph_json.cc), as the database keeps it.
std::string ViewpointDocument(const g::Viewpoint& v);
g::Viewpoint ViewpointFromDocument(const std::string& text);
std::string ParamsDocument(const FurnitureGraphParams& p);
FurnitureGraphParams ParamsFromDocument(const std::string& text);
// The graph as built, stored whole so that a later change of the building code cannot change a live conversation.
std::string GraphDocument(const g::FurnitureGraph& graph);
g::FurnitureGraph GraphFromDocument(const std::string& text);
// The knowledge document new graphs are created with: `text` checked and completed with the built-in tables.
std::string KnowledgeDocument(const std::string& text);
// A description as given (the input stored with it).
std::string DescriptionDocument(const DescriptionRequest& request);
DescriptionRequest DescriptionFromDocument(const std::string& text);

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
