#include "services/furniture/furniture_service.h"

#include <chrono>
#include <functional>

#include "services/furniture/furniture_service_internal.h"
#include "engine/grounding/parser.h"

namespace anchordb::services {

using namespace furniture_detail;  // NOLINT: the graph's helpers are this file's vocabulary

namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string SchemeName(const std::optional<g::Scheme>& s) { return s ? g::SchemeId(*s) : "none"; }

Json Distribution(const double* p, int n, const std::function<const char*(int)>& name) {
  Json out = Json::object();
  for (int i = 0; i < n; ++i) out[name(i)] = p[i];
  return out;
}

Json RelationDistribution(const double* p) {
  return Distribution(p, g::kRelationCount, [](int i) { return g::RelationId(static_cast<g::Relation>(i)); });
}

// A match as the client sees it: which pieces, which frame (and orientation of the reference for the intrinsic
// frame), and the relation as seen from the viewpoint.
Json MatchJson(const g::FurnitureGraph& graph, const g::Match& m) {
  Json out = {{"located", graph.vertices[static_cast<std::size_t>(graph.Located(m.directed_edge))].id},
              {"reference", graph.vertices[static_cast<std::size_t>(graph.Reference(m.directed_edge))].id},
              {"frame", g::FrameId(g::FrameOf(m.interpretation))},
              {"relation_seen", g::RelationId(m.relative)},
              {"scheme", g::SchemeId(m.scheme)},
              {"score", m.score}};
  out["reference_front"] = g::FrameOf(m.interpretation) == g::Frame::kIntrinsic ? Json(g::OrientationId(g::OrientationOf(m.interpretation))) : Json(nullptr);
  return out;
}

}  // namespace

FurnitureService::FurnitureService(storage::Store& store, FurnitureSettings settings)
    : store_(store), settings_(std::move(settings)), knowledge_doc_(KnowledgeDocument(settings_.knowledge_json)) {}

Json FurnitureService::Create(const std::string& map, const Json& body) {
  json::RejectUnknownKeys(body, {"viewpoint", "furniture", "params"});
  auto graph = std::make_shared<Graph>();
  graph->knowledge = g::LoadKnowledge(knowledge_doc_.dump());
  graph->viewpoint = ParseViewpoint(json::Require(body, "viewpoint"));
  graph->config = ParseConfig(body.contains("params") ? &body["params"] : nullptr, settings_);
  const auto furniture = ParseFurniture(json::Require(body, "furniture"), graph->knowledge.categories, settings_.max_furniture);
  graph->graph = g::BuildFurnitureGraph(graph->viewpoint, furniture, graph->knowledge.categories.size(),
                                        g::GraphParams{graph->config.edge_max_gap_m, graph->config.relation_sharpness});
  graph->set = g::InitialHypotheses(graph->graph);
  storage::FurnitureGraphRecord& r = graph->record;
  r.map_id = map;
  r.viewpoint_json = ViewpointJson(graph->viewpoint).dump();
  r.params_json = graph->config.ToJson().dump();
  r.knowledge_json = knowledge_doc_.dump();
  r.graph_json = GraphJson(graph->graph).dump();
  r.created_ns = r.updated_ns = NowNs();
  r.hypotheses = EncodeHypotheses(graph->graph, graph->set);
  r.id = store_.Write([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
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
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    return storage::FindFurnitureGraph(c, map, id, true);
  });
  if (!record) throw not_found();
  auto graph = std::make_shared<Graph>();
  graph->knowledge = g::LoadKnowledge(record->knowledge_json);
  graph->config = ConfigFromStored(Json::parse(record->params_json));
  const Json viewpoint = Json::parse(record->viewpoint_json);
  graph->viewpoint = ParseViewpoint(viewpoint);
  graph->graph = GraphFromJson(Json::parse(record->graph_json));
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

Json FurnitureService::View(const Graph& gr, const std::vector<storage::GraphDescriptionRecord>& descriptions) const {
  const g::FurnitureGraph& graph = gr.graph;
  const g::Hypothesis& best = gr.set.ranked.front();
  const int k = graph.category_count;
  const auto& cats = gr.knowledge.categories;
  Json vertices = Json::array();
  for (std::size_t i = 0; i < graph.vertices.size(); ++i) {
    const g::Vertex& v = graph.vertices[i];
    const double* pf = &best.state.category[i * static_cast<std::size_t>(k)];
    const double* po = &best.state.orientation[i * g::kOrientationCount];
    const int label = Argmax(pf, k), front = Argmax(po, g::kOrientationCount);
    const bool known_front = std::count(po, po + g::kOrientationCount, po[front]) == 1;
    vertices.push_back({{"id", v.id},
                        {"position", Vec(v.position_m)},
                        {"extent", Vec(v.extent_m)},
                        {"yaw_rad", v.yaw_rad},
                        {"label", cats[label].id},
                        {"label_probability", pf[label]},
                        {"categories", Distribution(pf, k, [&](int c) { return cats[c].id.c_str(); })},
                        {"front", known_front ? Json(g::OrientationId(static_cast<g::Orientation>(front))) : Json(nullptr)},
                        {"orientations", Distribution(po, g::kOrientationCount, [](int o) { return g::OrientationId(static_cast<g::Orientation>(o)); })}});
  }
  Json edges = Json::array();
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const g::Edge& edge = graph.edges[e];
    edges.push_back({{"a", graph.vertices[static_cast<std::size_t>(edge.a)].id},
                     {"b", graph.vertices[static_cast<std::size_t>(edge.b)].id},
                     {"gap_m", edge.gap_m},
                     {"a_relative_to_b", RelationDistribution(&best.state.relation[(2 * e) * g::kRelationCount])},
                     {"b_relative_to_a", RelationDistribution(&best.state.relation[(2 * e + 1) * g::kRelationCount])},
                     {"visual", {{"a_relative_to_b", RelationDistribution(edge.visual[0].data())},
                                 {"b_relative_to_a", RelationDistribution(edge.visual[1].data())}}}});
  }
  Json groundings = Json::array();
  for (std::size_t t = 0; t < best.matches.size(); ++t) {
    Json item = MatchJson(graph, best.matches[t]);
    item["seq"] = t + 1;
    if (t < descriptions.size()) {
      item["input"] = Json::parse(descriptions[t].input_json);
      item["understood"] = {{"located", descriptions[t].located}, {"relation", descriptions[t].relation},
                            {"reference", descriptions[t].reference}};
    }
    groundings.push_back(item);
  }
  return {{"id", gr.record.id},
          {"map", gr.record.map_id},
          {"viewpoint", ViewpointJson(gr.viewpoint)},
          {"params", gr.config.ToJson()},
          {"created_ns", gr.record.created_ns},
          {"updated_ns", gr.record.updated_ns},
          {"descriptions", gr.set.step},
          {"hypotheses", gr.set.ranked.size()},
          {"best", {{"hypothesis", best.id}, {"scheme", SchemeName(best.scheme)}, {"score", best.score}}},
          {"vertices", vertices},
          {"edges", edges},
          {"groundings", groundings}};
}

Json FurnitureService::List(const std::string& map, std::int64_t before_id, int limit) {
  return store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    Json out = {{"furniture_graphs", Json::array()}};
    for (const auto& r : storage::ListFurnitureGraphs(c, map, before_id, limit)) {
      out["furniture_graphs"].push_back({{"id", r.id}, {"viewpoint", Json::parse(r.viewpoint_json)}, {"params", Json::parse(r.params_json)},
                                         {"descriptions", r.descriptions}, {"created_ns", r.created_ns}, {"updated_ns", r.updated_ns}});
    }
    return out;
  });
}

Json FurnitureService::Get(const std::string& map, std::int64_t id) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const auto descriptions = store_.Read([&](storage::Connection& c) { return storage::ListGraphDescriptions(c, id); });
  return View(*graph, descriptions);
}

Json FurnitureService::Describe(const std::string& map, std::int64_t id, const Json& body) {
  json::RejectUnknownKeys(body, {"text", "located", "relation", "reference"});
  auto graph = Acquire(map, id);
  const g::CategoryTable& cats = graph->knowledge.categories;
  g::Description d;
  Json understood;
  if (body.contains("text")) {
    if (body.contains("located") || body.contains("relation") || body.contains("reference")) {
      BadArgument("give either text or located, relation and reference, not both", "text");
    }
    const std::string text = json::RequireString(body, "text", settings_.max_text_length);
    const g::ParsedDescription p = g::ParseSentence(text, cats, "text");
    d = p.description;
    understood = {{"words", {{"located", p.located_words}, {"relation", p.relation_words}, {"reference", p.reference_words}}}};
  } else {
    d.located = g::ParseCategory(json::RequireString(body, "located", 64), cats, "located");
    d.relation = g::ParseRelation(json::RequireString(body, "relation", 64), "relation");
    d.reference = g::ParseCategory(json::RequireString(body, "reference", 64), cats, "reference");
    understood = Json::object();
  }
  understood["located"] = cats[d.located].id;
  understood["relation"] = g::RelationId(d.relation);
  understood["reference"] = cats[d.reference].id;

  std::lock_guard<std::mutex> lock(graph->mutex);
  g::HypothesisSet next = g::Ground(graph->graph, graph->knowledge, graph->set, d, graph->config.Grounding());
  const std::string blob = EncodeHypotheses(graph->graph, next);
  const std::int64_t now = NowNs();
  store_.Write([&](storage::Connection& c) {
    storage::InsertGraphDescription(c, {id, next.step, body.dump(), cats[d.located].id, g::RelationId(d.relation), cats[d.reference].id, now});
    storage::UpdateFurnitureGraphState(c, id, next.step, blob, now, graph->record.state_version);
  });
  graph->record.state_version += 1;
  graph->record.updated_ns = now;
  graph->record.descriptions = next.step;
  graph->set = std::move(next);
  const g::Hypothesis& best = graph->set.ranked.front();
  Json sequence = Json::array();
  for (const g::Match& m : best.matches) sequence.push_back(MatchJson(graph->graph, m));
  // A revision: the best sequence no longer runs through the previous best hypothesis (figures 5.9-5.10).
  bool revised = false;
  for (std::size_t t = 0; t + 1 < best.lineage_ranks.size(); ++t) revised = revised || best.lineage_ranks[t] != 0;
  return {{"graph", id},
          {"seq", graph->set.step},
          {"understood", understood},
          {"match", MatchJson(graph->graph, best.matches.back())},
          {"best", {{"hypothesis", best.id}, {"scheme", SchemeName(best.scheme)}, {"score", best.score},
                    {"ancestor_ranks", best.lineage_ranks}, {"revised", revised}}},
          {"groundings", sequence},
          {"hypotheses", graph->set.ranked.size()}};
}

Json FurnitureService::Hypotheses(const std::string& map, std::int64_t id, int limit) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  const int k = graph->graph.category_count;
  Json list = Json::array();
  const std::size_t n = std::min(graph->set.ranked.size(), static_cast<std::size_t>(limit));
  for (std::size_t rank = 0; rank < n; ++rank) {
    const g::Hypothesis& h = graph->set.ranked[rank];
    Json labels = Json::object();
    for (std::size_t v = 0; v < graph->graph.vertices.size(); ++v) {
      labels[graph->graph.vertices[v].id] = graph->knowledge.categories[Argmax(&h.state.category[v * static_cast<std::size_t>(k)], k)].id;
    }
    list.push_back({{"rank", rank + 1},
                    {"id", h.id},
                    {"parent", h.parent_id < 0 ? Json(nullptr) : Json(h.parent_id)},
                    {"scheme", SchemeName(h.scheme)},
                    {"score", h.score},
                    {"ancestor_ranks", h.lineage_ranks},
                    {"last_match", h.matches.empty() ? Json(nullptr) : MatchJson(graph->graph, h.matches.back())},
                    {"labels", labels}});
  }
  return {{"graph", id}, {"descriptions", graph->set.step}, {"count", graph->set.ranked.size()}, {"hypotheses", list}};
}

Json FurnitureService::Reset(const std::string& map, std::int64_t id) {
  auto graph = Acquire(map, id);
  std::lock_guard<std::mutex> lock(graph->mutex);
  g::HypothesisSet initial = g::InitialHypotheses(graph->graph);
  const std::string blob = EncodeHypotheses(graph->graph, initial);
  const std::int64_t now = NowNs();
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
