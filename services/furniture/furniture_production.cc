// Speaking about the furniture of a graph: where a thing stands relative to it in the words the listener's grounding
// model prefers (Place, SPEC §4.4), and speech production (Produce).
#include "services/furniture/furniture_service.h"

#include <algorithm>

#include "services/furniture/furniture_service_internal.h"
#include "engine/events/placement.h"
#include "engine/grounding/parser.h"

namespace anchordb::services {

using namespace furniture_detail;  // NOLINT: the graph's helpers are this file's vocabulary

std::optional<Json> FurnitureService::Place(const std::string& map, const Eigen::Vector3d& p_M,
                                            std::optional<std::int64_t> graph_id) {
  if (!graph_id) graph_id = store_.Read([&](storage::Connection& c) { return storage::NewestFurnitureGraphId(c, map); });
  if (!graph_id) return std::nullopt;
  auto graph = Acquire(map, *graph_id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const g::Hypothesis& best = graph->set.ranked.front();
  const int k = graph->graph.category_count;
  std::vector<engine::FurniturePiece> pieces;
  std::vector<int> categories;
  for (std::size_t v = 0; v < graph->graph.vertices.size(); ++v) {
    const g::Vertex& vertex = graph->graph.vertices[v];
    categories.push_back(Argmax(&best.state.category[v * static_cast<std::size_t>(k)], k));
    pieces.push_back({vertex.id, graph->knowledge.categories[categories.back()].name, vertex.position_m, vertex.extent_m,
                      vertex.yaw_rad});
  }
  const engine::Placement placed = engine::PlaceObject(p_M, pieces, graph->viewpoint);
  const auto piece = static_cast<std::size_t>(placed.piece);
  Json out = {{"graph", graph->record.id}, {"furniture", pieces[piece].id},
              {"category", graph->knowledge.categories[categories[piece]].id}, {"name", pieces[piece].name},
              {"gap_m", placed.gap_m}};
  if (placed.on) {
    out["relation"] = "on";
    out["frame"] = nullptr;
    out["phrase"] = "on the " + pieces[piece].name;
    return out;
  }
  const g::Distribution4 relative = g::RelationFromOffset(
      graph->viewpoint.ToViewer(p_M.head<2>() - pieces[piece].position_m), graph->config.relation_sharpness);
  const g::WordChoice choice = g::PreferredWord(graph->knowledge, best, k, placed.piece, relative);
  out["relation"] = g::RelationId(choice.word);
  out["frame"] = g::FrameId(choice.frame);
  out["phrase"] = std::string(g::RelationPhrase(choice.word)) + " the " + pieces[piece].name;
  return out;
}

Json FurnitureService::Produce(const std::string& map, std::int64_t id, const Json& body) {
  json::RejectUnknownKeys(body, {"located", "reference"});
  const std::string located = json::RequireString(body, "located", 64), reference = json::RequireString(body, "reference", 64);
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const int a = graph->graph.VertexIndex(located), b = graph->graph.VertexIndex(reference);
  if (a < 0) throw Error(ErrorCode::kNotFound, "the graph has no vertex '" + located + "'", "located");
  if (b < 0) throw Error(ErrorCode::kNotFound, "the graph has no vertex '" + reference + "'", "reference");
  if (a == b) throw Error(ErrorCode::kUnprocessable, "located and reference are the same vertex", "reference");
  const g::Production p = g::Produce(graph->graph, graph->knowledge, graph->set.ranked.front(), a, b);
  const auto& cats = graph->knowledge.categories;
  Json alternatives = Json::array();
  std::vector<int> order = {0, 1, 2, 3};
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return p.word_probability[static_cast<std::size_t>(x)] > p.word_probability[static_cast<std::size_t>(y)];
  });
  for (int r : order) {
    alternatives.push_back({{"relation", g::RelationId(static_cast<g::Relation>(r))}, {"probability", p.word_probability[static_cast<std::size_t>(r)]}});
  }
  const std::string sentence = "the " + cats[p.located_category].name + " is " + g::RelationPhrase(p.relation) + " the " +
                               cats[p.reference_category].name;
  return {{"located", {{"vertex", located}, {"label", cats[p.located_category].id}, {"name", cats[p.located_category].name},
                       {"probability", p.located_probability}}},
          {"reference", {{"vertex", reference}, {"label", cats[p.reference_category].id}, {"name", cats[p.reference_category].name},
                         {"probability", p.reference_probability}}},
          {"relation", g::RelationId(p.relation)},
          {"phrase", g::RelationPhrase(p.relation)},
          {"frame", g::FrameId(p.frame)},
          {"probability", p.word_probability[static_cast<std::size_t>(p.relation)]},
          {"alternatives", alternatives},
          {"scheme", g::SchemeId(p.scheme)},
          {"sentence", sentence}};
}

}  // namespace anchordb::services
