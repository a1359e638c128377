// A furniture graph's viewpoint, parameters and graph, and a description's input, between the store's typed records
// (storage/furniture_repository.h, migration 0023) and the engine's and the service's types.
#include "services/furniture/furniture_service_internal.h"

namespace anchordb::services::furniture_detail {

namespace {

std::array<double, 2> Stored(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
Eigen::Vector2d Vec(const std::array<double, 2>& v) { return {v[0], v[1]}; }

Error Inconsistent(std::int64_t id, const std::string& what) {
  return Error(ErrorCode::kInternal, "stored furniture graph " + std::to_string(id) + " is inconsistent: " + what);
}

}  // namespace

void StoreGraph(storage::FurnitureGraphRecord& r, const g::Viewpoint& viewpoint, const FurnitureGraphParams& p,
                const g::FurnitureGraph& graph) {
  r.viewpoint_position_m = Stored(viewpoint.position_m);
  r.viewpoint_heading_rad = viewpoint.heading_rad;
  r.params = {g::ModelId(p.model), p.n_best, p.sigma, p.edge_max_gap_m, p.relation_sharpness, p.adaptation,
              p.frame_prior == FramePrior::kUniform ? "uniform" : "statistical", p.ambiguity_margin, p.category_floor,
              p.orientation_prior == OrientationPrior::kRoom ? "room" : "uniform", p.occupancy_layer};
  r.category_count = graph.category_count;
  r.vertices.clear();
  const std::size_t k = static_cast<std::size_t>(graph.category_count);
  for (std::size_t i = 0; i < graph.vertices.size(); ++i) {
    const g::Vertex& v = graph.vertices[i];
    storage::FurnitureVertexRecord& out = r.vertices.emplace_back();
    out.id = v.id;
    out.position_m = Stored(v.position_m);
    out.extent_m = Stored(v.extent_m);
    out.yaw_rad = v.yaw_rad;
    out.categories.assign(graph.initial.category.begin() + static_cast<std::ptrdiff_t>(i * k),
                          graph.initial.category.begin() + static_cast<std::ptrdiff_t>((i + 1) * k));
    for (std::size_t o = 0; o < g::kOrientationCount; ++o) out.orientations[o] = graph.initial.orientation[i * g::kOrientationCount + o];
  }
  r.edges.clear();
  for (const g::Edge& e : graph.edges) r.edges.push_back({e.a, e.b, e.gap_m, e.visual});
}

g::Viewpoint ViewpointOf(const storage::FurnitureGraphRecord& r) {
  g::Viewpoint v;
  v.position_m = Vec(r.viewpoint_position_m);
  v.heading_rad = r.viewpoint_heading_rad;
  return v;
}

FurnitureGraphParams ParamsOf(const storage::FurnitureGraphParamsRecord& r) {
  FurnitureGraphParams p;
  p.model = r.grounding_model == "joint" ? g::Model::kJoint : g::Model::kSequential;
  p.n_best = static_cast<int>(r.n_best);
  p.sigma = r.sigma;
  p.edge_max_gap_m = r.edge_max_gap_m;
  p.relation_sharpness = r.relation_sharpness;
  p.adaptation = r.adaptation;
  p.frame_prior = r.frame_prior == "uniform" ? FramePrior::kUniform : FramePrior::kStatistical;
  p.ambiguity_margin = r.ambiguity_margin;
  p.category_floor = r.category_floor;
  p.orientation_prior = r.orientation_prior == "room" ? OrientationPrior::kRoom : OrientationPrior::kUniform;
  p.occupancy_layer = r.occupancy_layer;
  return p;
}

g::FurnitureGraph GraphOf(const storage::FurnitureGraphRecord& r) {
  g::FurnitureGraph graph;
  graph.category_count = static_cast<int>(r.category_count);
  const int n = static_cast<int>(r.vertices.size());
  for (const storage::FurnitureVertexRecord& v : r.vertices) {
    graph.vertices.push_back({v.id, Vec(v.position_m), Vec(v.extent_m), v.yaw_rad});
    if (static_cast<std::int64_t>(v.categories.size()) != r.category_count) throw Inconsistent(r.id, "a vertex's p(f)");
    graph.initial.category.insert(graph.initial.category.end(), v.categories.begin(), v.categories.end());
    graph.initial.orientation.insert(graph.initial.orientation.end(), v.orientations.begin(), v.orientations.end());
  }
  for (const storage::FurnitureEdgeRecord& e : r.edges) {
    if (e.a < 0 || e.b < 0 || e.a >= n || e.b >= n) throw Inconsistent(r.id, "an edge's vertex");
    g::Edge edge;
    edge.a = static_cast<int>(e.a);
    edge.b = static_cast<int>(e.b);
    edge.gap_m = e.gap_m;
    edge.visual = e.visual;
    graph.edges.push_back(edge);
    for (const auto& p : edge.visual) graph.initial.relation.insert(graph.initial.relation.end(), p.begin(), p.end());
  }
  return graph;
}

void StoreInput(storage::GraphDescriptionRecord& r, const DescriptionRequest& request) {
  r.input_text = request.text;
  if (!request.text) {
    r.input_located = request.located;
    r.input_relation = request.relation;
    r.input_reference = request.reference;
  }
}

DescriptionRequest InputOf(const storage::GraphDescriptionRecord& r) {
  DescriptionRequest d;
  d.text = r.input_text;
  if (!r.input_text) {
    d.located = r.input_located;
    d.relation = r.input_relation;
    d.reference = r.input_reference;
  }
  return d;
}

}  // namespace anchordb::services::furniture_detail
