#include "services/furniture/furniture_service.h"

#include <algorithm>

#include "services/furniture/furniture_service_internal.h"
#include "engine/grounding/ambiguity.h"
#include "engine/grounding/orientation_prior.h"
#include "engine/grounding/readings.h"
#include "services/furniture/hypotheses_records.h"
#include "storage/event_repository.h"
#include "storage/repositories.h"

namespace anchordb::services {

using namespace furniture_detail;  // NOLINT: the graph's helpers are this file's vocabulary

namespace {

Error NoMap(const std::string& map) { return Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map"); }

// The map's furniture instances as pieces of a graph (CreateGraphRequest::from_instances).
std::vector<FurniturePieceRequest> PiecesFromInstances(storage::Store& store, const std::string& map, const g::CategoryTable& table) {
  std::vector<FurniturePieceRequest> out;
  store.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw NoMap(map);
    storage::InstanceFilter f;
    f.kind = "furniture";
    f.limit = 100000;
    for (const auto& r : storage::ListInstances(c, map, f, false)) {
      const std::map<std::string, double>& labels = r.labels;
      FurniturePieceRequest piece;
      piece.id = "f" + std::to_string(r.id);
      piece.position_m = Eigen::Vector2d(r.position[0], r.position[1]);
      piece.extent_m = Eigen::Vector2d(r.extent[0], r.extent[1]);
      piece.yaw_rad = r.yaw_rad;
      double sum = 0.0;
      for (const auto& [word, weight] : labels) {
        if (table.IndexOfWord(word) < 0) continue;
        piece.categories.push_back({word, weight});
        sum += weight;
      }
      if (sum > 0.0) out.push_back(std::move(piece));
    }
    return 0;
  });
  if (out.empty()) throw Error(ErrorCode::kUnprocessable, "the map has no furniture instance of a known category", "from_instances");
  return out;
}

}  // namespace

int furniture_detail::VertexOrNotFound(const g::FurnitureGraph& graph, const std::string& id, const char* field) {
  const int v = graph.VertexIndex(id);
  if (v < 0) throw Error(ErrorCode::kNotFound, "the graph has no vertex '" + id + "'", field);
  return v;
}

MatchView furniture_detail::MatchOf(const g::FurnitureGraph& graph, const g::Match& m) {
  MatchView out;
  out.located = graph.vertices[static_cast<std::size_t>(graph.Located(m.directed_edge))].id;
  out.reference = graph.vertices[static_cast<std::size_t>(graph.Reference(m.directed_edge))].id;
  out.frame = g::FrameOf(m.interpretation);
  out.relation_seen = m.relative;
  out.scheme = m.scheme;
  out.score = m.score;
  if (out.frame == g::Frame::kIntrinsic) out.reference_front = g::OrientationOf(m.interpretation);
  return out;
}

namespace {

BestHypothesis BestOf(const g::Hypothesis& h) { return {h.id, h.scheme, h.score}; }

g::Distribution4 RelationRow(const g::GraphState& s, std::size_t directed) {
  g::Distribution4 out{};
  for (std::size_t r = 0; r < g::kRelationCount; ++r) out[r] = s.relation[directed * g::kRelationCount + r];
  return out;
}

}  // namespace

FurnitureService::FurnitureService(storage::Store& store, FurnitureSettings settings, const Clock& clock)
    : store_(store), settings_(std::move(settings)), clock_(clock), knowledge_json_(g::CompleteKnowledgeJson(settings_.knowledge_json)) {}

GraphView FurnitureService::Create(const std::string& map, const CreateGraphRequest& request) {
  auto graph = std::make_shared<Graph>();
  graph->knowledge = g::LoadKnowledge(knowledge_json_);
  graph->viewpoint = request.viewpoint;
  graph->params = ResolveParams(request.params, settings_);
  const auto furniture = ResolveFurniture(request.from_instances ? PiecesFromInstances(store_, map, graph->knowledge.categories) : request.furniture,
                                          graph->knowledge.categories, settings_.max_furniture);
  graph->graph = g::BuildFurnitureGraph(graph->viewpoint, furniture, graph->knowledge.categories.size(),
                                        g::GraphParams{graph->params.edge_max_gap_m, graph->params.relation_sharpness});
  if (graph->params.orientation_prior == OrientationPrior::kRoom) {
    if (!request.params.occupancy_layer) graph->params.occupancy_layer = DefaultOccupancyLayer(store_, map);
    const auto occupancy = OccupancyOf(store_, map, graph->params.occupancy_layer);
    graph->graph.initial.orientation = g::RoomOrientationPrior(graph->viewpoint, furniture, graph->knowledge.categories,
                                                               g::RoomLayout{occupancy ? &*occupancy : nullptr, {}});
  }
  graph->set = g::InitialHypotheses(graph->graph);
  storage::FurnitureGraphRecord& r = graph->record;
  r.map_id = map;
  StoreGraph(r, graph->viewpoint, graph->params, graph->graph);
  r.knowledge_text = knowledge_json_;
  r.created_ns = r.updated_ns = clock_.NowNs();
  r.hypotheses = EncodeHypotheses(graph->graph, graph->set);
  r.id = store_.Write([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw NoMap(map);
    return storage::InsertFurnitureGraph(c, r);
  });
  r.hypotheses.clear();
  {
    std::lock_guard<std::mutex> lock(graphs_mutex_);
    graphs_[r.id] = graph;
  }
  std::lock_guard<std::mutex> lock(graph->mutex);
  return View(*graph, {});
}

std::shared_ptr<FurnitureService::Graph> FurnitureService::Acquire(const std::string& map, std::int64_t id) {
  const auto not_found = [&] {
    return Error(ErrorCode::kNotFound, "furniture graph " + std::to_string(id) + " does not exist in map '" + map + "'", "graph");
  };
  {
    std::lock_guard<std::mutex> lock(graphs_mutex_);
    auto it = graphs_.find(id);
    if (it != graphs_.end()) {
      if (it->second->record.map_id != map) throw not_found();
      return it->second;
    }
  }
  auto record = store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw NoMap(map);
    return storage::FindFurnitureGraph(c, map, id, true);
  });
  if (!record) throw not_found();
  auto graph = std::make_shared<Graph>();
  graph->knowledge = g::LoadKnowledge(record->knowledge_text);
  graph->params = ParamsOf(record->params);
  graph->viewpoint = ViewpointOf(*record);
  graph->graph = GraphOf(*record);
  g::SetLineOfSight(graph->graph, graph->viewpoint, graph->params.relation_sharpness);
  graph->set = DecodeHypotheses(graph->graph, record->hypotheses);
  record->hypotheses.clear();
  graph->record = std::move(*record);
  std::lock_guard<std::mutex> lock(graphs_mutex_);
  // Keep the cache bounded: drop graphs nobody is using (they reload from the database on demand).
  if (graphs_.size() >= 64) {
    for (auto it = graphs_.begin(); it != graphs_.end();) it = it->second.use_count() == 1 ? graphs_.erase(it) : std::next(it);
  }
  auto [it, inserted] = graphs_.emplace(id, graph);
  return it->second;  // another thread may have loaded it first: use that one
}

GraphView FurnitureService::View(const Graph& gr, const std::vector<storage::GraphDescriptionRecord>& descriptions) const {
  const g::FurnitureGraph& graph = gr.graph;
  const g::Hypothesis& best = gr.set.ranked.front();
  const int k = graph.category_count;
  const auto& cats = gr.knowledge.categories;
  GraphView out;
  out.id = gr.record.id;
  out.map = gr.record.map_id;
  out.viewpoint = gr.viewpoint;
  out.params = gr.params;
  out.created_ns = gr.record.created_ns;
  out.updated_ns = gr.record.updated_ns;
  out.descriptions = gr.set.step;
  out.hypotheses = gr.set.ranked.size();
  out.best = BestOf(best);
  for (std::size_t i = 0; i < graph.vertices.size(); ++i) {
    const g::Vertex& v = graph.vertices[i];
    const double* pf = &best.state.category[i * static_cast<std::size_t>(k)];
    const int label = g::MostProbableCategory(best.state, k, static_cast<int>(i));
    VertexView& view = out.vertices.emplace_back();
    view.id = v.id;
    view.position_m = v.position_m;
    view.extent_m = v.extent_m;
    view.yaw_rad = v.yaw_rad;
    view.label = cats[label].id;
    view.label_probability = pf[label];
    for (int c = 0; c < k; ++c) view.categories.push_back({cats[c].id, pf[c]});
    view.front = g::KnownFront(best.state, static_cast<int>(i));
    for (std::size_t o = 0; o < g::kOrientationCount; ++o) view.orientations[o] = best.state.orientation[i * g::kOrientationCount + o];
  }
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const g::Edge& edge = graph.edges[e];
    out.edges.push_back({graph.vertices[static_cast<std::size_t>(edge.a)].id, graph.vertices[static_cast<std::size_t>(edge.b)].id,
                         edge.gap_m, RelationRow(best.state, 2 * e), RelationRow(best.state, 2 * e + 1), edge.visual[0],
                         edge.visual[1]});
  }
  for (std::size_t t = 0; t < best.matches.size(); ++t) {
    GroundedDescription& item = out.groundings.emplace_back();
    item.seq = static_cast<int>(t + 1);
    item.match = MatchOf(graph, best.matches[t]);
    if (t < descriptions.size()) {
      item.input = InputOf(descriptions[t]);
      item.understood = Understood{descriptions[t].located, descriptions[t].relation, descriptions[t].reference, std::nullopt};
    }
  }
  out.pending = PendingOf(gr);
  return out;
}

std::vector<GraphSummary> FurnitureService::List(const std::string& map, std::int64_t before_id, int limit) {
  return store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw NoMap(map);
    std::vector<GraphSummary> out;
    for (const auto& r : storage::ListFurnitureGraphs(c, map, before_id, limit)) {
      out.push_back({r.id, ViewpointOf(r), ParamsOf(r.params), r.descriptions,
                     r.created_ns, r.updated_ns});
    }
    return out;
  });
}

GraphView FurnitureService::Get(const std::string& map, std::int64_t id) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const auto descriptions = store_.Read([&](storage::Connection& c) { return storage::ListGraphDescriptions(c, id); });
  return View(*graph, descriptions);
}

GroundingResult FurnitureService::Describe(const std::string& map, std::int64_t id, const DescriptionRequest& request) {
  auto graph = Acquire(map, id);
  const g::CategoryTable& cats = graph->knowledge.categories;
  const ResolvedDescription resolved = ResolveDescription(request, cats);
  const g::Description& d = resolved.description;

  std::lock_guard<std::mutex> lock(graph->mutex);
  const g::GroundingParams params = GroundingParamsOf(graph->params);
  std::vector<int> held_before;
  for (const g::HeldStep& h : graph->set.held) held_before.push_back(h.step);
  g::HypothesisSet next = g::Ground(graph->graph, graph->knowledge, graph->set, d, params);
  const std::string blob = EncodeHypotheses(graph->graph, next);
  const std::int64_t now = clock_.NowNs();
  store_.Write([&](storage::Connection& c) {
    storage::GraphDescriptionRecord described;
    described.graph_id = id;
    described.seq = next.step;
    StoreInput(described, request);
    described.located = resolved.understood.located;
    described.relation = resolved.understood.relation;
    described.reference = resolved.understood.reference;
    described.created_ns = now;
    storage::InsertGraphDescription(c, described);
    storage::UpdateFurnitureGraphState(c, id, next.step, blob, now, graph->record.state_version);
  });
  graph->record.state_version += 1;
  graph->record.updated_ns = now;
  graph->record.descriptions = next.step;
  graph->set = std::move(next);
  const g::Hypothesis& best = graph->set.ranked.front();
  GroundingResult out;
  out.graph = id;
  out.seq = graph->set.step;
  out.understood = resolved.understood;
  out.match = MatchOf(graph->graph, best.matches.back());
  out.best = BestOf(best);
  out.ancestor_ranks = best.lineage_ranks;
  out.revised = g::IsRevised(best);
  for (const g::Match& m : best.matches) out.groundings.push_back(MatchOf(graph->graph, m));
  out.hypotheses = graph->set.ranked.size();
  const int step = graph->set.step - 1;
  const auto is_held = [&](int t) {
    return std::any_of(graph->set.held.begin(), graph->set.held.end(), [t](const g::HeldStep& h) { return h.step == t; });
  };
  const bool ambiguous = is_held(step);
  const bool poor = params.category_floor > 0.0 && g::IsPoorMatch(graph->graph, best.state, d, best.matches.back(), params.category_floor);
  if (ambiguous || poor) out.ambiguity = AmbiguityOf(*graph, step, d, ambiguous, poor);
  for (const int t : held_before) {
    if (!is_held(t)) out.settled.push_back(t + 1);
  }
  return out;
}

GraphView FurnitureService::Resolve(const std::string& map, std::int64_t id, const ResolveRequest& request) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const int a = VertexOrNotFound(graph->graph, request.located, "located");
  const int b = VertexOrNotFound(graph->graph, request.reference, "reference");
  if (graph->set.held.empty()) throw Error(ErrorCode::kConflict, "no description of this graph is awaiting a resolution", "seq");
  const std::int64_t seq = request.seq.value_or(graph->set.held.front().step + 1);
  if (seq < 1 || seq > graph->set.step) throw Error(ErrorCode::kUnprocessable, "seq must name a grounded description", "seq");
  g::HypothesisSet next = graph->set;
  g::KeepPair(graph->graph, next, static_cast<int>(seq - 1), a, b, GroundingParamsOf(graph->params));
  const std::string blob = EncodeHypotheses(graph->graph, next);
  const std::int64_t now = clock_.NowNs();
  store_.Write([&](storage::Connection& c) {
    storage::UpdateFurnitureGraphState(c, id, next.step, blob, now, graph->record.state_version);
  });
  graph->record.state_version += 1;
  graph->record.updated_ns = now;
  graph->set = std::move(next);
  const auto descriptions = store_.Read([&](storage::Connection& c) { return storage::ListGraphDescriptions(c, id); });
  return View(*graph, descriptions);
}

HypothesisList FurnitureService::Hypotheses(const std::string& map, std::int64_t id, int limit) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const int k = graph->graph.category_count;
  HypothesisList out;
  out.graph = id;
  out.descriptions = graph->set.step;
  out.count = graph->set.ranked.size();
  const std::size_t n = std::min(graph->set.ranked.size(), static_cast<std::size_t>(limit));
  for (std::size_t rank = 0; rank < n; ++rank) {
    const g::Hypothesis& h = graph->set.ranked[rank];
    HypothesisView& view = out.hypotheses.emplace_back();
    view.rank = static_cast<int>(rank + 1);
    view.id = h.id;
    if (h.parent_id >= 0) view.parent = h.parent_id;
    view.scheme = h.scheme;
    view.score = h.score;
    view.ancestor_ranks = h.lineage_ranks;
    if (!h.matches.empty()) view.last_match = MatchOf(graph->graph, h.matches.back());
    for (std::size_t v = 0; v < graph->graph.vertices.size(); ++v) {
      view.labels.push_back({graph->graph.vertices[v].id,
                             graph->knowledge.categories[g::MostProbableCategory(h.state, k, static_cast<int>(v))].id});
    }
  }
  return out;
}

GraphView FurnitureService::Reset(const std::string& map, std::int64_t id) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  g::HypothesisSet initial = g::InitialHypotheses(graph->graph);
  const std::string blob = EncodeHypotheses(graph->graph, initial);
  const std::int64_t now = clock_.NowNs();
  store_.Write([&](storage::Connection& c) {
    storage::DeleteGraphDescriptions(c, id);
    storage::UpdateFurnitureGraphState(c, id, 0, blob, now, graph->record.state_version);
  });
  graph->record.state_version += 1;
  graph->record.updated_ns = now;
  graph->record.descriptions = 0;
  graph->set = std::move(initial);
  return View(*graph, {});
}

}  // namespace anchordb::services
