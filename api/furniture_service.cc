#include "api/furniture_service.h"

#include "engine/events/placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>

#include "engine/grounding/parser.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::api {

namespace g = engine::grounding;

namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

[[noreturn]] void BadArgument(const std::string& message, const std::string& field) {
  throw Error(ErrorCode::kInvalidArgument, message, field);
}

// [x, y] or [x, y, z] (z ignored: graphs are planar) with finite numbers.
Eigen::Vector2d AsPlanar(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() < 2 || v.size() > 3) BadArgument(field + " must be [x, y] or [x, y, z] in metres", field);
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) out[i] = json::AsFiniteNumber(v[static_cast<std::size_t>(i)], field);
  if (v.size() == 3) json::AsFiniteNumber(v[2], field);
  return out;
}

Json Vec(const Eigen::Vector2d& v) { return Json::array({v.x(), v.y()}); }

g::Viewpoint ParseViewpoint(const Json& j) {
  if (!j.is_object()) BadArgument("viewpoint must be an object {position:[x,y], heading_rad}", "viewpoint");
  json::RejectUnknownKeys(j, {"position", "heading_rad"}, "viewpoint");
  g::Viewpoint v;
  v.position_m = AsPlanar(json::Require(j, "position", "viewpoint"), "viewpoint.position");
  v.heading_rad = json::RequireFiniteNumber(j, "heading_rad", "viewpoint");
  return v;
}

Json ViewpointJson(const g::Viewpoint& v) { return {{"position", Vec(v.position_m)}, {"heading_rad", v.heading_rad}}; }

// {"sofa": 0.7, "armchair": 0.2, ...}: category words or ids of the table, non-negative, normalised here.
std::vector<double> ParseCategories(const Json& j, const g::CategoryTable& table, const std::string& field) {
  if (!j.is_object() || j.empty()) {
    BadArgument(field + " must be an object of category probabilities, e.g. {\"sofa\": 0.7, \"armchair\": 0.3}", field);
  }
  std::vector<double> p(static_cast<std::size_t>(table.size()), 0.0);
  double sum = 0.0;
  for (const auto& [word, value] : j.items()) {
    const int c = g::ParseCategory(word, table, field + "." + word);
    const double v = json::AsFiniteNumber(value, field + "." + word);
    if (v < 0.0) throw Error(ErrorCode::kUnprocessable, "category probabilities must not be negative", field + "." + word);
    p[static_cast<std::size_t>(c)] += v;
    sum += v;
  }
  if (!(sum > 0.0)) throw Error(ErrorCode::kUnprocessable, "category probabilities must not all be zero", field);
  for (double& v : p) v /= sum;
  return p;
}

std::vector<g::FurnitureInput> ParseFurniture(const Json& j, const g::CategoryTable& table, int max_furniture) {
  if (!j.is_array()) BadArgument("furniture must be an array of pieces", "furniture");
  if (static_cast<int>(j.size()) > max_furniture) {
    throw Error(ErrorCode::kPayloadTooLarge, "at most " + std::to_string(max_furniture) + " furniture pieces per graph", "furniture");
  }
  std::vector<g::FurnitureInput> out;
  std::set<std::string> ids;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string f = "furniture[" + std::to_string(i) + "]";
    const Json& piece = j[i];
    if (!piece.is_object()) BadArgument(f + " must be an object", f);
    json::RejectUnknownKeys(piece, {"id", "position", "extent", "yaw_rad", "categories"}, f);
    g::FurnitureInput in;
    if (piece.contains("id")) {
      in.id = json::RequireId(piece, "id", f);
    } else {
      in.id = std::to_string(i + 1);
      in.id.insert(in.id.begin(), 'v');  // not "v" + ...: GCC 12 -O3 raises a false -Wrestrict on that form
    }
    if (!ids.insert(in.id).second) throw Error(ErrorCode::kConflict, "furniture id '" + in.id + "' is given twice", f + ".id");
    in.position_m = AsPlanar(json::Require(piece, "position", f), f + ".position");
    if (piece.contains("extent")) {
      in.extent_m = AsPlanar(piece["extent"], f + ".extent");
      if (in.extent_m.minCoeff() < 0.0) throw Error(ErrorCode::kUnprocessable, "extent must not be negative", f + ".extent");
    }
    in.yaw_rad = json::FiniteNumberOr(piece, "yaw_rad", 0.0, f);
    in.category = ParseCategories(json::Require(piece, "categories", f), table, f + ".categories");
    out.push_back(std::move(in));
  }
  return out;
}

struct GraphConfig {
  int n_best = 100;
  double sigma = 3.0;
  double edge_max_gap_m = 1.5;
  double relation_sharpness = 3.0;
  bool adaptation = true;
  std::string frame_prior = "statistical";

  Json ToJson() const {
    return {{"n_best", n_best}, {"sigma", sigma}, {"edge_max_gap_m", edge_max_gap_m}, {"relation_sharpness", relation_sharpness},
            {"adaptation", adaptation}, {"frame_prior", frame_prior}};
  }
  g::GroundingParams Grounding() const {
    g::GroundingParams p;
    p.n_best = n_best;
    p.sigma = sigma;
    const g::Scheme base = frame_prior == "uniform" ? g::Scheme::kUniform : g::Scheme::kStatistical;
    p.schemes = adaptation ? std::vector<g::Scheme>{base, g::Scheme::kRelative, g::Scheme::kIntrinsic} : std::vector<g::Scheme>{base};
    return p;
  }
};

GraphConfig ParseConfig(const Json* j, const FurnitureSettings& s) {
  GraphConfig c;
  c.n_best = s.n_best;
  c.sigma = s.sigma;
  c.edge_max_gap_m = s.edge_max_gap_m;
  c.relation_sharpness = s.relation_sharpness;
  if (!j) return c;
  if (!j->is_object()) BadArgument("params must be an object", "params");
  json::RejectUnknownKeys(*j, {"n_best", "sigma", "edge_max_gap_m", "relation_sharpness", "adaptation", "frame_prior"}, "params");
  const std::int64_t n = json::IntegerOr(*j, "n_best", c.n_best, "params");
  if (n < 1 || n > s.max_n_best) {
    throw Error(ErrorCode::kUnprocessable, "n_best must be in [1, " + std::to_string(s.max_n_best) + "]", "params.n_best");
  }
  c.n_best = static_cast<int>(n);
  c.sigma = json::FiniteNumberOr(*j, "sigma", c.sigma, "params");
  if (c.sigma < 1.0 || c.sigma > 1000.0) throw Error(ErrorCode::kUnprocessable, "sigma must be in [1, 1000]", "params.sigma");
  c.edge_max_gap_m = json::FiniteNumberOr(*j, "edge_max_gap_m", c.edge_max_gap_m, "params");
  if (c.edge_max_gap_m < 0.0 || c.edge_max_gap_m > 100.0) {
    throw Error(ErrorCode::kUnprocessable, "edge_max_gap_m must be in [0, 100] m", "params.edge_max_gap_m");
  }
  c.relation_sharpness = json::FiniteNumberOr(*j, "relation_sharpness", c.relation_sharpness, "params");
  if (c.relation_sharpness < 0.0 || c.relation_sharpness > 100.0) {
    throw Error(ErrorCode::kUnprocessable, "relation_sharpness must be in [0, 100]", "params.relation_sharpness");
  }
  c.adaptation = json::BoolOr(*j, "adaptation", true, "params");
  c.frame_prior = json::OptionalString(*j, "frame_prior", 16, "params").value_or("statistical");
  if (c.frame_prior != "statistical" && c.frame_prior != "uniform") {
    BadArgument("frame_prior must be statistical or uniform", "params.frame_prior");
  }
  return c;
}

GraphConfig ConfigFromStored(const Json& j) {
  GraphConfig c;
  c.n_best = j.at("n_best").get<int>();
  c.sigma = j.at("sigma").get<double>();
  c.edge_max_gap_m = j.at("edge_max_gap_m").get<double>();
  c.relation_sharpness = j.at("relation_sharpness").get<double>();
  c.adaptation = j.at("adaptation").get<bool>();
  c.frame_prior = j.at("frame_prior").get<std::string>();
  return c;
}

// The graph as built, stored whole so that a later change of the building code cannot change a live conversation.
Json GraphJson(const g::FurnitureGraph& graph) {
  Json vertices = Json::array(), edges = Json::array();
  const std::size_t k = static_cast<std::size_t>(graph.category_count);
  for (std::size_t i = 0; i < graph.vertices.size(); ++i) {
    const g::Vertex& v = graph.vertices[i];
    std::vector<double> pf(graph.initial.category.begin() + static_cast<std::ptrdiff_t>(i * k),
                           graph.initial.category.begin() + static_cast<std::ptrdiff_t>((i + 1) * k));
    vertices.push_back({{"id", v.id}, {"position", Vec(v.position_m)}, {"extent", Vec(v.extent_m)}, {"yaw_rad", v.yaw_rad},
                        {"categories", pf}});
  }
  for (const g::Edge& e : graph.edges) {
    edges.push_back({{"a", e.a}, {"b", e.b}, {"gap_m", e.gap_m}, {"visual", {e.visual[0], e.visual[1]}}});
  }
  return {{"category_count", graph.category_count}, {"vertices", vertices}, {"edges", edges}};
}

g::FurnitureGraph GraphFromJson(const Json& j) {
  g::FurnitureGraph graph;
  graph.category_count = j.at("category_count").get<int>();
  for (const Json& v : j.at("vertices")) {
    const auto pos = v.at("position").get<std::vector<double>>(), ext = v.at("extent").get<std::vector<double>>();
    graph.vertices.push_back({v.at("id").get<std::string>(), {pos.at(0), pos.at(1)}, {ext.at(0), ext.at(1)}, v.at("yaw_rad").get<double>()});
    const auto pf = v.at("categories").get<std::vector<double>>();
    if (static_cast<int>(pf.size()) != graph.category_count) throw Error(ErrorCode::kInternal, "stored graph is inconsistent");
    graph.initial.category.insert(graph.initial.category.end(), pf.begin(), pf.end());
    for (int o = 0; o < g::kOrientationCount; ++o) graph.initial.orientation.push_back(1.0 / g::kOrientationCount);
  }
  for (const Json& e : j.at("edges")) {
    g::Edge edge;
    edge.a = e.at("a").get<int>();
    edge.b = e.at("b").get<int>();
    edge.gap_m = e.at("gap_m").get<double>();
    for (int d = 0; d < 2; ++d) {
      const auto p = e.at("visual").at(static_cast<std::size_t>(d)).get<std::vector<double>>();
      for (int r = 0; r < g::kRelationCount; ++r) edge.visual[static_cast<std::size_t>(d)][static_cast<std::size_t>(r)] = p.at(static_cast<std::size_t>(r));
    }
    graph.edges.push_back(edge);
    for (const auto& p : edge.visual) graph.initial.relation.insert(graph.initial.relation.end(), p.begin(), p.end());
  }
  return graph;
}

Json KnowledgeDocument(const std::string& text) {
  if (text.empty()) {
    return {{"categories", Json::parse(g::DefaultCategoriesJson())}, {"frame_prior", Json::parse(g::DefaultFramePriorJson())}};
  }
  const g::Knowledge check = g::LoadKnowledge(text);  // throws naming the bad entry
  (void)check;
  Json doc = Json::parse(text);
  if (!doc.contains("categories")) doc["categories"] = Json::parse(g::DefaultCategoriesJson());
  if (!doc.contains("frame_prior")) doc["frame_prior"] = Json::parse(g::DefaultFramePriorJson());
  return doc;
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

int Argmax(const double* p, int n) { return static_cast<int>(std::max_element(p, p + n) - p); }

}  // namespace

struct FurnitureService::Graph {
  std::mutex mutex;
  storage::FurnitureGraphRecord record;  // hypotheses blob not kept here
  g::FurnitureGraph graph;
  g::Knowledge knowledge;
  GraphConfig config;
  g::Viewpoint viewpoint;
  g::HypothesisSet set;
};

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

}  // namespace anchordb::api
