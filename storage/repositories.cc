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
