#include "engine/events/graph_placement.h"

#include "engine/events/placement.h"
#include "engine/grounding/readings.h"

namespace anchordb::engine {

GraphPlacement PlaceInGraph(const grounding::FurnitureGraph& graph, const grounding::Knowledge& knowledge,
                            const grounding::Hypothesis& best, const grounding::Viewpoint& viewpoint,
                            double relation_sharpness, const Eigen::Vector3d& p_map) {
  const int k = graph.category_count;
  std::vector<FurniturePiece> pieces;
  for (std::size_t v = 0; v < graph.vertices.size(); ++v) {
    const grounding::Vertex& vertex = graph.vertices[v];
    const int category = grounding::MostProbableCategory(best.state, k, static_cast<int>(v));
    pieces.push_back({vertex.id, knowledge.categories[category].name, vertex.position_m, vertex.extent_m, vertex.yaw_rad});
  }
  const Placement placed = PlaceObject(p_map, pieces, viewpoint);
  GraphPlacement out;
  out.vertex = placed.piece;
  out.category = grounding::MostProbableCategory(best.state, k, placed.piece);
  out.on = placed.on;
  out.gap_m = placed.gap_m;
  if (placed.on) return out;
  const grounding::Distribution4 relative = grounding::RelationFromOffset(
      viewpoint.ToViewer(p_map.head<2>() - pieces[static_cast<std::size_t>(placed.piece)].position_m), relation_sharpness);
  const grounding::WordChoice choice = grounding::PreferredWord(knowledge, best, k, placed.piece, relative);
  out.word = choice.word;
  out.frame = choice.frame;
  return out;
}

}  // namespace anchordb::engine
