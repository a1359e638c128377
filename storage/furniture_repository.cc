#include "storage/furniture_repository.h"

#include "schema/error.h"

namespace anchordb::storage {
namespace {

constexpr const char* kGraphColumns =
    "id, map_id, viewpoint_x_m, viewpoint_y_m, viewpoint_heading_rad, grounding_model, n_best, sigma, edge_max_gap_m, "
    "relation_sharpness, adaptation, frame_prior, ambiguity_margin, category_floor, orientation_prior, "
    "occupancy_layer, knowledge, category_count, created_ns, updated_ns, descriptions, state_version";

FurnitureGraphRecord ReadGraph(const Statement& s, bool with_hypotheses) {
  FurnitureGraphRecord r;
  r.id = s.Int(0);
  r.map_id = s.Text(1);
  r.viewpoint_position_m = {s.Double(2), s.Double(3)};
  r.viewpoint_heading_rad = s.Double(4);
  FurnitureGraphParamsRecord& p = r.params;
  p.grounding_model = s.Text(5);
  p.n_best = s.Int(6);
  p.sigma = s.Double(7);
  p.edge_max_gap_m = s.Double(8);
  p.relation_sharpness = s.Double(9);
  p.adaptation = s.Int(10) != 0;
  p.frame_prior = s.Text(11);
  p.ambiguity_margin = s.Double(12);
  p.category_floor = s.Double(13);
  p.orientation_prior = s.Text(14);
  p.occupancy_layer = s.Text(15);
  r.knowledge_text = s.Text(16);
  r.category_count = s.Int(17);
  r.created_ns = s.Int(18);
  r.updated_ns = s.Int(19);
  r.descriptions = s.Int(20);
  r.state_version = s.Int(21);
  if (with_hypotheses) r.hypotheses = s.Blob(22);
  return r;
}

// The vertices with their categories, and the edges, of graph `r` (read in one read transaction by the caller).
void ReadGraphStructure(Connection& c, FurnitureGraphRecord& r) {
  {
    Statement s(c, "SELECT vertex_id, x_m, y_m, extent_x_m, extent_y_m, yaw_rad, orientation_p0, orientation_p1, "
                   "orientation_p2, orientation_p3 FROM furniture_graph_vertices WHERE graph_id = ? ORDER BY position");
    s.Bind(1, r.id);
    while (s.Step()) {
      r.vertices.push_back({s.Text(0), {s.Double(1), s.Double(2)}, {s.Double(3), s.Double(4)}, s.Double(5), {},
                            {s.Double(6), s.Double(7), s.Double(8), s.Double(9)}});
    }
  }
  {
    Statement s(c, "SELECT vertex, category, p FROM furniture_graph_vertex_categories WHERE graph_id = ? "
                   "ORDER BY vertex, category");
    s.Bind(1, r.id);
    while (s.Step()) {
      const std::int64_t vertex = s.Int(0);
      if (vertex < 0 || vertex >= static_cast<std::int64_t>(r.vertices.size()) ||
          s.Int(1) != static_cast<std::int64_t>(r.vertices[static_cast<std::size_t>(vertex)].categories.size())) {
        throw Error(ErrorCode::kInternal, "stored furniture graph " + std::to_string(r.id) + " is inconsistent");
      }
      r.vertices[static_cast<std::size_t>(vertex)].categories.push_back(s.Double(2));
    }
  }
  Statement s(c, "SELECT a, b, gap_m, ab_p0, ab_p1, ab_p2, ab_p3, ba_p0, ba_p1, ba_p2, ba_p3 FROM furniture_graph_edges "
                 "WHERE graph_id = ? ORDER BY position");
  s.Bind(1, r.id);
  while (s.Step()) {
    r.edges.push_back({s.Int(0), s.Int(1), s.Double(2),
                       {{{s.Double(3), s.Double(4), s.Double(5), s.Double(6)},
                         {s.Double(7), s.Double(8), s.Double(9), s.Double(10)}}}});
  }
}

void InsertGraphStructure(Connection& c, std::int64_t id, const FurnitureGraphRecord& r) {
  for (std::size_t i = 0; i < r.vertices.size(); ++i) {
    const FurnitureVertexRecord& v = r.vertices[i];
    Statement s(c, "INSERT INTO furniture_graph_vertices (graph_id, position, vertex_id, x_m, y_m, extent_x_m, "
                   "extent_y_m, yaw_rad, orientation_p0, orientation_p1, orientation_p2, orientation_p3) "
                   "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    s.Bind(1, id).Bind(2, static_cast<std::int64_t>(i)).Bind(3, v.id).Bind(4, v.position_m[0]).Bind(5, v.position_m[1])
        .Bind(6, v.extent_m[0]).Bind(7, v.extent_m[1]).Bind(8, v.yaw_rad);
    for (int k = 0; k < 4; ++k) s.Bind(9 + k, v.orientations[static_cast<std::size_t>(k)]);
    s.Run();
    for (std::size_t f = 0; f < v.categories.size(); ++f) {
      Statement(c, "INSERT INTO furniture_graph_vertex_categories (graph_id, vertex, category, p) VALUES (?, ?, ?, ?)")
          .Bind(1, id).Bind(2, static_cast<std::int64_t>(i)).Bind(3, static_cast<std::int64_t>(f)).Bind(4, v.categories[f])
          .Run();
    }
  }
  for (std::size_t i = 0; i < r.edges.size(); ++i) {
    const FurnitureEdgeRecord& e = r.edges[i];
    Statement s(c, "INSERT INTO furniture_graph_edges (graph_id, position, a, b, gap_m, ab_p0, ab_p1, ab_p2, ab_p3, "
                   "ba_p0, ba_p1, ba_p2, ba_p3) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    s.Bind(1, id).Bind(2, static_cast<std::int64_t>(i)).Bind(3, e.a).Bind(4, e.b).Bind(5, e.gap_m);
    for (int d = 0; d < 2; ++d) {
      for (int k = 0; k < 4; ++k) s.Bind(6 + 4 * d + k, e.visual[static_cast<std::size_t>(d)][static_cast<std::size_t>(k)]);
    }
    s.Run();
  }
}

}  // namespace

std::int64_t InsertFurnitureGraph(Connection& c, const FurnitureGraphRecord& r) {
  Statement s(c, "INSERT INTO furniture_graphs (map_id, viewpoint_x_m, viewpoint_y_m, viewpoint_heading_rad, "
                 "grounding_model, n_best, sigma, edge_max_gap_m, relation_sharpness, adaptation, frame_prior, "
                 "ambiguity_margin, category_floor, orientation_prior, occupancy_layer, knowledge, category_count, "
                 "created_ns, updated_ns, descriptions, state_version, hypotheses) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 0, ?) RETURNING id");
  const FurnitureGraphParamsRecord& p = r.params;
  s.Bind(1, r.map_id).Bind(2, r.viewpoint_position_m[0]).Bind(3, r.viewpoint_position_m[1]).Bind(4, r.viewpoint_heading_rad)
      .Bind(5, p.grounding_model).Bind(6, p.n_best).Bind(7, p.sigma).Bind(8, p.edge_max_gap_m).Bind(9, p.relation_sharpness)
      .Bind(10, std::int64_t{p.adaptation}).Bind(11, p.frame_prior).Bind(12, p.ambiguity_margin).Bind(13, p.category_floor)
      .Bind(14, p.orientation_prior).Bind(15, p.occupancy_layer).Bind(16, r.knowledge_text).Bind(17, r.category_count)
      .Bind(18, r.created_ns).Bind(19, r.updated_ns).Bind(20, r.descriptions).BindBlob(21, r.hypotheses);
  const std::int64_t id = s.RunReturningId();
  InsertGraphStructure(c, id, r);
  return id;
}

std::optional<FurnitureGraphRecord> FindFurnitureGraph(Connection& c, const std::string& map_id, std::int64_t id,
                                                       bool with_hypotheses) {
  std::optional<FurnitureGraphRecord> r;
  {
    Statement s(c, std::string("SELECT ") + kGraphColumns + (with_hypotheses ? ", hypotheses" : "") +
                       " FROM furniture_graphs WHERE map_id = ? AND id = ?");
    s.Bind(1, map_id).Bind(2, id);
    if (!s.Step()) return std::nullopt;
    r = ReadGraph(s, with_hypotheses);
  }
  ReadGraphStructure(c, *r);
  return r;
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
  Statement s(c, "INSERT INTO furniture_graph_descriptions (graph_id, seq, input_text, input_located, input_relation, "
                 "input_reference, located, relation, reference, created_ns) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  s.Bind(1, d.graph_id).Bind(2, d.seq);
  if (d.input_text) {
    s.Bind(3, *d.input_text).BindNull(4).BindNull(5).BindNull(6);
  } else {
    s.BindNull(3).Bind(4, d.input_located).Bind(5, d.input_relation).Bind(6, d.input_reference);
  }
  s.Bind(7, d.located).Bind(8, d.relation).Bind(9, d.reference).Bind(10, d.created_ns).Run();
}

std::vector<GraphDescriptionRecord> ListGraphDescriptions(Connection& c, std::int64_t graph_id) {
  Statement s(c, "SELECT graph_id, seq, input_text, input_located, input_relation, input_reference, located, relation, "
                 "reference, created_ns FROM furniture_graph_descriptions WHERE graph_id = ? ORDER BY seq");
  s.Bind(1, graph_id);
  std::vector<GraphDescriptionRecord> out;
  while (s.Step()) {
    GraphDescriptionRecord d;
    d.graph_id = s.Int(0);
    d.seq = s.Int(1);
    if (!s.IsNull(2)) d.input_text = s.Text(2);
    const auto text_or_empty = [&](int column) { return s.IsNull(column) ? std::string() : s.Text(column); };
    d.input_located = text_or_empty(3);
    d.input_relation = text_or_empty(4);
    d.input_reference = text_or_empty(5);
    d.located = s.Text(6);
    d.relation = s.Text(7);
    d.reference = s.Text(8);
    d.created_ns = s.Int(9);
    out.push_back(std::move(d));
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
