#pragma once
// SQL for furniture graphs (thesis 5.3): the graph rows (viewpoint and parameters in typed columns, the graph's
// vertices, categories and edges in child tables since migration 0023) with their live hypotheses, and the stream of
// grounded descriptions. The knowledge text is opaque here (the engine's knowledge format, as the operator gave it);
// services/furniture/ maps the records to the engine's types, storage/hypotheses_codec.h gives the blob its meaning.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct FurnitureGraphParamsRecord {
  std::string grounding_model = "sequential";  // sequential | joint
  std::int64_t n_best = 0;
  double sigma = 0.0;
  double edge_max_gap_m = 0.0;
  double relation_sharpness = 0.0;
  bool adaptation = false;
  std::string frame_prior = "statistical";  // uniform | statistical
  double ambiguity_margin = 0.0;
  double category_floor = 0.0;
  std::string orientation_prior = "uniform";  // uniform | room
  std::string occupancy_layer;
};

struct FurnitureVertexRecord {
  std::string id;
  std::array<double, 2> position_m{};
  std::array<double, 2> extent_m{};
  double yaw_rad = 0.0;
  std::vector<double> categories;       // p(f), category_count values
  std::array<double, 4> orientations{};  // p(o)
};

struct FurnitureEdgeRecord {
  std::int64_t a = 0;
  std::int64_t b = 0;
  double gap_m = 0.0;
  std::array<std::array<double, 4>, 2> visual{};  // p(r) per direction: a relative to b, b relative to a
};

struct FurnitureGraphRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::array<double, 2> viewpoint_position_m{};
  double viewpoint_heading_rad = 0.0;
  FurnitureGraphParamsRecord params;
  std::string knowledge_text;  // the knowledge tables the graph grounds with, in the engine's format
  std::int64_t category_count = 0;
  // Loaded by FindFurnitureGraph only (a listing leaves them empty).
  std::vector<FurnitureVertexRecord> vertices;
  std::vector<FurnitureEdgeRecord> edges;
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
// Graphs of a map with id < before_id (0 = from the newest), newest first, at most `limit`; no hypotheses, vertices
// or edges.
std::vector<FurnitureGraphRecord> ListFurnitureGraphs(Connection& c, const std::string& map_id, std::int64_t before_id,
                                                      int limit);
// Replaces the hypotheses and the description count and sets state_version = expected + 1; kConflict when the
// stored state_version is not `expected_state_version` (another writer got there first).
void UpdateFurnitureGraphState(Connection& c, std::int64_t id, std::int64_t descriptions, const std::string& hypotheses,
                               std::int64_t updated_ns, std::int64_t expected_state_version);

struct GraphDescriptionRecord {
  std::int64_t graph_id = 0;
  std::int64_t seq = 0;
  // The description as received: its text, or (input_text nullopt) the three names it gave.
  std::optional<std::string> input_text;
  std::string input_located;
  std::string input_relation;
  std::string input_reference;
  // As understood:
  std::string located;
  std::string relation;
  std::string reference;
  std::int64_t created_ns = 0;
};
void InsertGraphDescription(Connection& c, const GraphDescriptionRecord& description);  // kConflict on a taken seq
std::vector<GraphDescriptionRecord> ListGraphDescriptions(Connection& c, std::int64_t graph_id);
void DeleteGraphDescriptions(Connection& c, std::int64_t graph_id);

}  // namespace anchordb::storage
