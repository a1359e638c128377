#pragma once
// SQL for furniture graphs (thesis 5.3): the graph rows with their live hypotheses, and the stream of grounded
// descriptions. The JSON columns and the hypotheses blob are opaque here; services/furniture/ gives the documents their
// meaning, storage/hypotheses_codec.h the blob.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct FurnitureGraphRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::string viewpoint_json;
  std::string params_json;
  std::string knowledge_json;
  std::string graph_json;
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
  std::int64_t descriptions = 0;
  std::int64_t state_version = 0;
  std::string hypotheses;  // blob; empty when not loaded
};

// Inserts (state_version 0) and returns the new id.
std::int64_t InsertFurnitureGraph(Connection& c, const FurnitureGraphRecord& graph);
std::optional<FurnitureGraphRecord> FindFurnitureGraph(Connection& c, const std::string& map_id, std::int64_t id,
                                                       bool with_hypotheses);
// The id of the map's newest graph, if any.
std::optional<std::int64_t> NewestFurnitureGraphId(Connection& c, const std::string& map_id);
// Graphs of a map with id < before_id (0 = from the newest), newest first, at most `limit`; no hypotheses.
std::vector<FurnitureGraphRecord> ListFurnitureGraphs(Connection& c, const std::string& map_id, std::int64_t before_id,
                                                      int limit);
// Replaces the hypotheses and the description count and sets state_version = expected + 1; kConflict when the
// stored state_version is not `expected_state_version` (another writer got there first).
void UpdateFurnitureGraphState(Connection& c, std::int64_t id, std::int64_t descriptions, const std::string& hypotheses,
                               std::int64_t updated_ns, std::int64_t expected_state_version);

struct GraphDescriptionRecord {
  std::int64_t graph_id = 0;
  std::int64_t seq = 0;
  std::string input_json;
  std::string located;
  std::string relation;
  std::string reference;
  std::int64_t created_ns = 0;
};
void InsertGraphDescription(Connection& c, const GraphDescriptionRecord& description);  // kConflict on a taken seq
std::vector<GraphDescriptionRecord> ListGraphDescriptions(Connection& c, std::int64_t graph_id);
void DeleteGraphDescriptions(Connection& c, std::int64_t graph_id);

}  // namespace anchordb::storage
