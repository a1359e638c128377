#include "storage/furniture_repository.h"

#include "schema/error.h"

namespace anchordb::storage {
namespace {

constexpr const char* kGraphColumns =
    "id, map_id, viewpoint, params, knowledge, graph, created_ns, updated_ns, descriptions, state_version";

FurnitureGraphRecord ReadGraph(const Statement& s, bool with_hypotheses) {
  FurnitureGraphRecord r;
  r.id = s.Int(0);
  r.map_id = s.Text(1);
  r.viewpoint_json = s.Text(2);
  r.params_json = s.Text(3);
  r.knowledge_json = s.Text(4);
  r.graph_json = s.Text(5);
  r.created_ns = s.Int(6);
  r.updated_ns = s.Int(7);
  r.descriptions = s.Int(8);
  r.state_version = s.Int(9);
  if (with_hypotheses) r.hypotheses = s.Blob(10);
  return r;
}

}  // namespace

std::int64_t InsertFurnitureGraph(Connection& c, const FurnitureGraphRecord& r) {
  Statement s(c, "INSERT INTO furniture_graphs (map_id, viewpoint, params, knowledge, graph, created_ns, updated_ns, "
                 "descriptions, state_version, hypotheses) VALUES (?, ?, ?, ?, ?, ?, ?, ?, 0, ?) RETURNING id");
  s.Bind(1, r.map_id).Bind(2, r.viewpoint_json).Bind(3, r.params_json).Bind(4, r.knowledge_json).Bind(5, r.graph_json)
      .Bind(6, r.created_ns).Bind(7, r.updated_ns).Bind(8, r.descriptions).BindBlob(9, r.hypotheses);
  return s.RunReturningId();
}

std::optional<FurnitureGraphRecord> FindFurnitureGraph(Connection& c, const std::string& map_id, std::int64_t id,
                                                       bool with_hypotheses) {
  Statement s(c, std::string("SELECT ") + kGraphColumns + (with_hypotheses ? ", hypotheses" : "") +
                     " FROM furniture_graphs WHERE map_id = ? AND id = ?");
  s.Bind(1, map_id).Bind(2, id);
  if (!s.Step()) return std::nullopt;
  return ReadGraph(s, with_hypotheses);
}

std::vector<FurnitureGraphRecord> ListFurnitureGraphs(Connection& c, const std::string& map_id, std::int64_t before_id,
                                                      int limit) {
  Statement s(c, std::string("SELECT ") + kGraphColumns +
                     " FROM furniture_graphs WHERE map_id = ?1 AND (?2 = 0 OR id < ?2) ORDER BY id DESC LIMIT ?3");
  s.Bind(1, map_id).Bind(2, before_id).Bind(3, static_cast<std::int64_t>(limit));
  std::vector<FurnitureGraphRecord> out;
  while (s.Step()) out.push_back(ReadGraph(s, false));
  return out;
}

void UpdateFurnitureGraphState(Connection& c, std::int64_t id, std::int64_t descriptions, const std::string& hypotheses,
                               std::int64_t updated_ns, std::int64_t expected) {
  Statement s(c, "UPDATE furniture_graphs SET descriptions = ?, hypotheses = ?, updated_ns = ?, state_version = ? "
                 "WHERE id = ? AND state_version = ?");
  s.Bind(1, descriptions).BindBlob(2, hypotheses).Bind(3, updated_ns).Bind(4, expected + 1).Bind(5, id).Bind(6, expected).Run();
  if (c.Changes() != 1) {
    throw Error(ErrorCode::kConflict, "furniture graph " + std::to_string(id) + " was changed concurrently");
  }
}

void InsertGraphDescription(Connection& c, const GraphDescriptionRecord& d) {
  Statement s(c, "INSERT INTO furniture_graph_descriptions (graph_id, seq, input, located, relation, reference, created_ns) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?)");
  s.Bind(1, d.graph_id).Bind(2, d.seq).Bind(3, d.input_json).Bind(4, d.located).Bind(5, d.relation).Bind(6, d.reference)
      .Bind(7, d.created_ns).Run();
}

std::vector<GraphDescriptionRecord> ListGraphDescriptions(Connection& c, std::int64_t graph_id) {
  Statement s(c, "SELECT graph_id, seq, input, located, relation, reference, created_ns FROM furniture_graph_descriptions "
                 "WHERE graph_id = ? ORDER BY seq");
  s.Bind(1, graph_id);
  std::vector<GraphDescriptionRecord> out;
  while (s.Step()) {
    out.push_back({s.Int(0), s.Int(1), s.Text(2), s.Text(3), s.Text(4), s.Text(5), s.Int(6)});
  }
  return out;
}

void DeleteGraphDescriptions(Connection& c, std::int64_t graph_id) {
  Statement s(c, "DELETE FROM furniture_graph_descriptions WHERE graph_id = ?");
  s.Bind(1, graph_id).Run();
}

std::optional<std::int64_t> NewestFurnitureGraphId(Connection& c, const std::string& map_id) {
  Statement s(c, "SELECT MAX(id) FROM furniture_graphs WHERE map_id = ?");
  s.Bind(1, map_id);
  if (!s.Step()) return std::nullopt;
  return OptionalInt(s, 0);
}

}  // namespace anchordb::storage
