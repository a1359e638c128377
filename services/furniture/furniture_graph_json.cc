// Furniture-graph requests and the stored form of a graph: the viewpoint, the furniture pieces and the params parsed
// strictly; the graph, its params and the knowledge document as the database keeps them.
#include <set>

#include "services/furniture/furniture_service_internal.h"
#include "engine/grounding/parser.h"

namespace anchordb::services::furniture_detail {

namespace {

// [x, y] or [x, y, z] (z ignored: graphs are planar) with finite numbers.
Eigen::Vector2d AsPlanar(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() < 2 || v.size() > 3) BadArgument(field + " must be [x, y] or [x, y, z] in metres", field);
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) out[i] = json::AsFiniteNumber(v[static_cast<std::size_t>(i)], field);
  if (v.size() == 3) json::AsFiniteNumber(v[2], field);
  return out;
}

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

}  // namespace

g::Viewpoint ParseViewpoint(const Json& j) {
  if (!j.is_object()) BadArgument("viewpoint must be an object {position:[x,y], heading_rad}", "viewpoint");
  json::RejectUnknownKeys(j, {"position", "heading_rad"}, "viewpoint");
  g::Viewpoint v;
  v.position_m = AsPlanar(json::Require(j, "position", "viewpoint"), "viewpoint.position");
  v.heading_rad = json::RequireFiniteNumber(j, "heading_rad", "viewpoint");
  return v;
}

Json ViewpointJson(const g::Viewpoint& v) { return {{"position", Vec(v.position_m)}, {"heading_rad", v.heading_rad}}; }

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

}  // namespace anchordb::services::furniture_detail
