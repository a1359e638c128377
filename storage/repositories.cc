#include "storage/repositories.h"

#include "storage/dialect.h"

#include "schema/error.h"

namespace anchordb::storage {

// ---- maps

void InsertMap(Connection& c, const MapRecord& m) {
  if (FindMap(c, m.id)) throw Error(ErrorCode::kConflict, "map '" + m.id + "' already exists", "id");
  Statement(c, "INSERT INTO maps (id, name, created_ns) VALUES (?, ?, ?)")
      .Bind(1, m.id).Bind(2, m.name).Bind(3, m.created_ns).Run();
}

std::optional<MapRecord> FindMap(Connection& c, const std::string& id) {
  Statement s(c, "SELECT id, name, created_ns FROM maps WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return MapRecord{s.Text(0), s.Text(1), s.Int(2)};
}

std::vector<MapRecord> ListMaps(Connection& c, const std::string& after_id, int limit) {
  Statement s(c, "SELECT id, name, created_ns FROM maps WHERE id > ? ORDER BY id LIMIT ?");
  s.Bind(1, after_id).Bind(2, static_cast<std::int64_t>(limit));
  std::vector<MapRecord> out;
  while (s.Step()) out.push_back({s.Text(0), s.Text(1), s.Int(2)});
  return out;
}

bool DeleteMap(Connection& c, const std::string& id) {
  // Dependencies between layers reference layers of the same map; remove them first so the cascade is free.
  Statement(c, "DELETE FROM layer_dependencies WHERE map_id = ?").Bind(1, id).Run();
  Statement s(c, "DELETE FROM maps WHERE id = ?");
  s.Bind(1, id).Run();
  return c.Changes() > 0;
}

// ---- layers

std::optional<LayerKind> LayerKindFromName(const std::string& n) {
  if (n == "occupancy") return LayerKind::kOccupancy;
  if (n == "probability") return LayerKind::kProbability;
  if (n == "fused") return LayerKind::kFused;
  if (n == "label") return LayerKind::kLabel;
  return std::nullopt;
}

void InsertLayer(Connection& c, const LayerRecord& l, const std::vector<std::string>& depends_on) {
  if (FindLayer(c, l.map_id, l.name, false)) {
    throw Error(ErrorCode::kConflict, "layer '" + l.name + "' already exists in map '" + l.map_id + "'", "layer");
  }
  Statement s(c, "INSERT INTO layers (map_id, name, kind, meta, data, version, created_ns, updated_ns) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  s.Bind(1, l.map_id).Bind(2, l.name).Bind(3, std::string_view(LayerKindName(l.kind))).Bind(4, l.meta_json);
  if (l.data.empty()) s.BindNull(5); else s.BindBlob(5, l.data);
  s.Bind(6, l.version).Bind(7, l.created_ns).Bind(8, l.updated_ns).Run();
  for (const std::string& d : depends_on) {
    Statement(c, "INSERT INTO layer_dependencies (map_id, layer, depends_on) VALUES (?, ?, ?) ON CONFLICT DO NOTHING")
        .Bind(1, l.map_id).Bind(2, l.name).Bind(3, d).Run();
  }
}

namespace {
LayerRecord ReadLayerRow(Statement& s, bool with_data) {
  LayerRecord l;
  l.map_id = s.Text(0);
  l.name = s.Text(1);
  l.kind = LayerKindFromName(s.Text(2)).value_or(LayerKind::kOccupancy);
  l.meta_json = s.Text(3);
  l.version = s.Int(4);
  l.created_ns = s.Int(5);
  l.updated_ns = s.Int(6);
  l.data_bytes = s.Int(7);
  if (with_data) l.data = s.Blob(8);
  return l;
}
}  // namespace

std::optional<LayerRecord> FindLayer(Connection& c, const std::string& map_id, const std::string& name, bool with_data) {
  Statement s(c, with_data ? "SELECT map_id, name, kind, meta, version, created_ns, updated_ns, "
                             "coalesce(length(data), 0), data FROM layers WHERE map_id = ? AND name = ?"
                           : "SELECT map_id, name, kind, meta, version, created_ns, updated_ns, "
                             "coalesce(length(data), 0) FROM layers WHERE map_id = ? AND name = ?");
  s.Bind(1, map_id).Bind(2, name);
  if (!s.Step()) return std::nullopt;
  return ReadLayerRow(s, with_data);
}

std::vector<LayerRecord> ListLayers(Connection& c, const std::string& map_id) {
  Statement s(c, "SELECT map_id, name, kind, meta, version, created_ns, updated_ns, coalesce(length(data), 0) "
                 "FROM layers WHERE map_id = ? ORDER BY name");
  s.Bind(1, map_id);
  std::vector<LayerRecord> out;
  while (s.Step()) out.push_back(ReadLayerRow(s, false));
  return out;
}

void UpdateLayer(Connection& c, const LayerRecord& l, std::int64_t expected_version) {
  Statement s(c, "UPDATE layers SET meta = ?, data = ?, version = ?, updated_ns = ? "
                 "WHERE map_id = ? AND name = ? AND version = ?");
  s.Bind(1, l.meta_json);
  if (l.data.empty()) s.BindNull(2); else s.BindBlob(2, l.data);
  s.Bind(3, l.version).Bind(4, l.updated_ns).Bind(5, l.map_id).Bind(6, l.name).Bind(7, expected_version).Run();
  if (c.Changes() != 1) {
    throw Error(ErrorCode::kConflict, "layer '" + l.name + "' changed concurrently (expected version " +
                                          std::to_string(expected_version) + ")");
  }
}

std::vector<std::string> LayerDependents(Connection& c, const std::string& map_id, const std::string& name) {
  Statement s(c, "SELECT layer FROM layer_dependencies WHERE map_id = ? AND depends_on = ? ORDER BY layer");
  s.Bind(1, map_id).Bind(2, name);
  std::vector<std::string> out;
  while (s.Step()) out.push_back(s.Text(0));
  return out;
}

bool DeleteLayer(Connection& c, const std::string& map_id, const std::string& name) {
  Statement(c, "DELETE FROM layers WHERE map_id = ? AND name = ?").Bind(1, map_id).Bind(2, name).Run();
  return c.Changes() > 0;
}

// ---- agents

void UpsertAgent(Connection& c, const std::string& map_id, const Agent& a) {
  Statement(c, "INSERT INTO agents (map_id, id, x_m, y_m, heading_rad, vx_mps, vy_mps, stamp_ns) "
               "VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (map_id, id) DO UPDATE SET x_m = excluded.x_m, "
               "y_m = excluded.y_m, heading_rad = excluded.heading_rad, vx_mps = excluded.vx_mps, "
               "vy_mps = excluded.vy_mps, stamp_ns = excluded.stamp_ns")
      .Bind(1, map_id).Bind(2, a.id).Bind(3, a.position_m.x()).Bind(4, a.position_m.y()).Bind(5, a.heading_rad)
      .Bind(6, a.velocity_mps.x()).Bind(7, a.velocity_mps.y()).Bind(8, a.stamp_ns).Run();
}

namespace {
Agent ReadAgentRow(Statement& s) {
  Agent a;
  a.id = s.Text(0);
  a.position_m = {s.Double(1), s.Double(2)};
  a.heading_rad = s.Double(3);
  a.velocity_mps = {s.Double(4), s.Double(5)};
  a.stamp_ns = s.Int(6);
  return a;
}
}  // namespace

std::optional<Agent> FindAgent(Connection& c, const std::string& map_id, const std::string& id) {
  Statement s(c, "SELECT id, x_m, y_m, heading_rad, vx_mps, vy_mps, stamp_ns FROM agents WHERE map_id = ? AND id = ?");
  s.Bind(1, map_id).Bind(2, id);
  if (!s.Step()) return std::nullopt;
  return ReadAgentRow(s);
}

std::vector<Agent> ListAgents(Connection& c, const std::string& map_id, const std::optional<Bbox>& bbox) {
  std::vector<Agent> out;
  if (bbox) {
    // The spatial index narrows by box (SQLite's R*Tree has conservative float bounds); the exact test follows.
    const std::string in_box = PointInBox(c.engine(), {"agents_rtree", "rowid_key", "a.rowid_key", "a.x_m", "a.y_m", ""},
                                          {"?", "?", "?", "?", "", ""});
    Statement s(c, "SELECT a.id, a.x_m, a.y_m, a.heading_rad, a.vx_mps, a.vy_mps, a.stamp_ns FROM agents a "
                   "WHERE a.map_id = ? AND " + in_box + " AND a.x_m BETWEEN ? AND ? AND a.y_m BETWEEN ? AND ? ORDER BY a.id");
    s.Bind(1, map_id).Bind(2, bbox->max_x).Bind(3, bbox->max_y).Bind(4, bbox->min_x).Bind(5, bbox->min_y)
        .Bind(6, bbox->min_x).Bind(7, bbox->max_x).Bind(8, bbox->min_y).Bind(9, bbox->max_y);
    while (s.Step()) out.push_back(ReadAgentRow(s));
  } else {
    Statement s(c, "SELECT id, x_m, y_m, heading_rad, vx_mps, vy_mps, stamp_ns FROM agents WHERE map_id = ? ORDER BY id");
    s.Bind(1, map_id);
    while (s.Step()) out.push_back(ReadAgentRow(s));
  }
  return out;
}

bool DeleteAgent(Connection& c, const std::string& map_id, const std::string& id) {
  Statement(c, "DELETE FROM agents WHERE map_id = ? AND id = ?").Bind(1, map_id).Bind(2, id).Run();
  return c.Changes() > 0;
}

// ---- tokens

void InsertToken(Connection& c, const TokenRecord& t) {
  Statement(c, "INSERT INTO tokens (id, sha256_hex, role, created_ns) VALUES (?, ?, ?, ?)")
      .Bind(1, t.id).Bind(2, t.sha256_hex).Bind(3, t.role).Bind(4, t.created_ns).Run();
}

std::optional<TokenRecord> FindTokenById(Connection& c, const std::string& id) {
  Statement s(c, "SELECT id, sha256_hex, role, created_ns FROM tokens WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return TokenRecord{s.Text(0), s.Text(1), s.Text(2), s.Int(3)};
}

std::vector<TokenRecord> ListTokens(Connection& c) {
  Statement s(c, "SELECT id, sha256_hex, role, created_ns FROM tokens ORDER BY id");
  std::vector<TokenRecord> out;
  while (s.Step()) out.push_back({s.Text(0), s.Text(1), s.Text(2), s.Int(3)});
  return out;
}

std::int64_t CountTokens(Connection& c) {
  Statement s(c, "SELECT count(*) FROM tokens");
  s.Step();
  return s.Int(0);
}

}  // namespace anchordb::storage
