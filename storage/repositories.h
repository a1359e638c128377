#pragma once
// Repositories: the SQL for each entity, as functions over a Connection (the caller picks a reader, or the
// writer inside Store::Write). Records carry what the rows hold; meaning is given by api/ and engine/.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "schema/types.h"
#include "storage/connection.h"
#include "storage/layer_meta.h"

namespace anchordb::storage {

// ---- maps
struct MapRecord {
  std::string id;
  std::string name;
  std::int64_t created_ns = 0;
};
void InsertMap(Connection& c, const MapRecord& map);  // kConflict if the id exists
std::optional<MapRecord> FindMap(Connection& c, const std::string& id);
// Maps with id > after_id in id order, at most `limit`.
std::vector<MapRecord> ListMaps(Connection& c, const std::string& after_id, int limit);
bool DeleteMap(Connection& c, const std::string& id);  // cascades to everything of the map

// ---- layers
struct LayerRecord {
  std::string map_id;
  std::string name;
  LayerKind kind = LayerKind::kOccupancy;
  StoredLayerMeta meta;  // the alternative of `kind` (storage/layer_codec.h keeps the two in step)
  std::string data;  // blob (empty when not loaded, or for fused layers)
  std::int64_t version = 1;
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
  std::int64_t data_bytes = 0;  // stored blob size
};
void InsertLayer(Connection& c, const LayerRecord& layer, const std::vector<std::string>& depends_on);
std::optional<LayerRecord> FindLayer(Connection& c, const std::string& map_id, const std::string& name, bool with_data);
// The layer's row without its blob in exactly one statement (for Store::ReadOneStatement). `complete` is false when
// the layer's metadata has list rows (fused operands, label names, ignored YAML keys) that only FindLayer reads.
struct LayerRecordRow {
  LayerRecord record;
  bool complete = true;
};
std::optional<LayerRecordRow> FindLayerRow(Connection& c, const std::string& map_id, const std::string& name);
std::vector<LayerRecord> ListLayers(Connection& c, const std::string& map_id);
// Replaces meta (of the same kind) and data and sets version/updated_ns. kConflict when `expected_version` is not the stored one.
void UpdateLayer(Connection& c, const LayerRecord& layer, std::int64_t expected_version);
std::vector<std::string> LayerDependents(Connection& c, const std::string& map_id, const std::string& name);
bool DeleteLayer(Connection& c, const std::string& map_id, const std::string& name);
std::optional<LayerKind> LayerKindFromName(const std::string& name);

// ---- agents (positions indexed in the agents_rtree R*Tree)
void UpsertAgent(Connection& c, const std::string& map_id, const Agent& agent);
std::optional<Agent> FindAgent(Connection& c, const std::string& map_id, const std::string& id);
struct Bbox {
  double min_x, min_y, max_x, max_y;
};
std::vector<Agent> ListAgents(Connection& c, const std::string& map_id, const std::optional<Bbox>& bbox);
bool DeleteAgent(Connection& c, const std::string& map_id, const std::string& id);

// ---- API tokens (only the SHA-256 of a token is stored)
struct TokenRecord {
  std::string id;
  std::string sha256_hex;
  std::string role;  // reader | writer | admin
  std::int64_t created_ns = 0;
};
void InsertToken(Connection& c, const TokenRecord& token);
std::optional<TokenRecord> FindTokenById(Connection& c, const std::string& id);
// Every token (for the constant-time match of tokens made before their secret carried their id).
std::vector<TokenRecord> ListTokens(Connection& c);
std::int64_t CountTokens(Connection& c);

}  // namespace anchordb::storage
