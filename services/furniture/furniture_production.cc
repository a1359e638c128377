// Speaking about the furniture of a graph: where a thing stands relative to it in the words the listener's grounding
// model prefers (Place, SPEC §4.4), and speech production (Produce).
#include "services/furniture/furniture_service.h"

#include "services/furniture/furniture_service_internal.h"
#include "engine/events/graph_placement.h"
#include "engine/grounding/readings.h"
#include "storage/furniture_repository.h"

namespace anchordb::services {

using furniture_detail::VertexOrNotFound;

std::optional<Placement> FurnitureService::Place(const std::string& map, const Eigen::Vector3d& p_map,
                                                 std::optional<std::int64_t> graph_id) {
  if (!graph_id) graph_id = store_.Read([&](storage::Connection& c) { return storage::NewestFurnitureGraphId(c, map); });
  if (!graph_id) return std::nullopt;
  auto graph = Acquire(map, *graph_id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const engine::GraphPlacement placed = engine::PlaceInGraph(graph->graph, graph->knowledge, graph->set.ranked.front(),
                                                             graph->viewpoint, graph->params.relation_sharpness, p_map);
  const g::Category& category = graph->knowledge.categories[placed.category];
  Placement out;
  out.graph = graph->record.id;
  out.furniture = graph->graph.vertices[static_cast<std::size_t>(placed.vertex)].id;
  out.category = category.id;
  out.name = category.name;
  out.gap_m = placed.gap_m;
  out.relation = placed.on ? "on" : g::RelationId(placed.word);
  if (!placed.on) out.frame = g::FrameId(placed.frame);
  out.phrase = g::PlacementPhrase(placed.on ? std::nullopt : std::optional<g::Relation>(placed.word), category.name);
  return out;
}

Utterance FurnitureService::Produce(const std::string& map, std::int64_t id, const ProduceRequest& request) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const int a = VertexOrNotFound(graph->graph, request.located, "located");
  const int b = VertexOrNotFound(graph->graph, request.reference, "reference");
  if (a == b) throw Error(ErrorCode::kUnprocessable, "located and reference are the same vertex", "reference");
  const g::Production p = g::Produce(graph->graph, graph->knowledge, graph->set.ranked.front(), a, b);
  const auto& cats = graph->knowledge.categories;
  Utterance out;
  out.located = {request.located, cats[p.located_category].id, cats[p.located_category].name, p.located_probability};
  out.reference = {request.reference, cats[p.reference_category].id, cats[p.reference_category].name, p.reference_probability};
  out.relation = p.relation;
  out.frame = p.frame;
  out.probability = p.word_probability[static_cast<std::size_t>(p.relation)];
  for (g::Relation r : g::WordsByProbability(p.word_probability)) {
    out.alternatives.push_back({r, p.word_probability[static_cast<std::size_t>(r)]});
  }
  out.scheme = p.scheme;
  out.sentence = g::ProductionSentence(cats[p.located_category].name, p.relation, cats[p.reference_category].name);
  return out;
}

}  // namespace anchordb::services
