// The stored form of a furniture graph: the viewpoint, the params, the graph as built, the knowledge document and
// each description's input, as the database keeps them (JSON documents).
#include <nlohmann/json.hpp>

#include "services/furniture/furniture_service_internal.h"

namespace anchordb::services::furniture_detail {

namespace {

using Json = nlohmann::json;

Json Vec(const Eigen::Vector2d& v) { return Json::array({v.x(), v.y()}); }

Eigen::Vector2d AsVec(const Json& j) {
  const auto v = j.get<std::vector<double>>();
  return {v.at(0), v.at(1)};
}

}  // namespace

std::string ViewpointDocument(const g::Viewpoint& v) {
  return Json{{"position", Vec(v.position_m)}, {"heading_rad", v.heading_rad}}.dump();
}

g::Viewpoint ViewpointFromDocument(const std::string& text) {
  const Json j = Json::parse(text);
  g::Viewpoint v;
  v.position_m = AsVec(j.at("position"));
  v.heading_rad = j.at("heading_rad").get<double>();
  return v;
}

std::string ParamsDocument(const FurnitureGraphParams& p) {
  return Json{{"model", g::ModelId(p.model)},
              {"n_best", p.n_best},
              {"sigma", p.sigma},
              {"edge_max_gap_m", p.edge_max_gap_m},
              {"relation_sharpness", p.relation_sharpness},
              {"adaptation", p.adaptation},
              {"frame_prior", p.frame_prior == FramePrior::kUniform ? "uniform" : "statistical"},
              {"ambiguity_margin", p.ambiguity_margin},
              {"category_floor", p.category_floor},
              {"orientation_prior", p.orientation_prior == OrientationPrior::kRoom ? "room" : "uniform"},
              {"occupancy_layer", p.occupancy_layer}}
      .dump();
}

FurnitureGraphParams ParamsFromDocument(const std::string& text) {
  const Json j = Json::parse(text);
  FurnitureGraphParams p;
  // Graphs stored before the joint model existed were scored sequentially.
  p.model = j.value("model", std::string("sequential")) == "joint" ? g::Model::kJoint : g::Model::kSequential;
  p.n_best = j.at("n_best").get<int>();
  p.sigma = j.at("sigma").get<double>();
  p.edge_max_gap_m = j.at("edge_max_gap_m").get<double>();
  p.relation_sharpness = j.at("relation_sharpness").get<double>();
  p.adaptation = j.at("adaptation").get<bool>();
  const std::string prior = j.at("frame_prior").get<std::string>();
  p.frame_prior = prior == "uniform" ? FramePrior::kUniform : FramePrior::kStatistical;
  // Graphs stored before issue 17 keep the thesis' behaviour.
  p.ambiguity_margin = j.value("ambiguity_margin", 0.0);
  p.category_floor = j.value("category_floor", 0.0);
  p.orientation_prior = j.value("orientation_prior", std::string("uniform")) == "room" ? OrientationPrior::kRoom : OrientationPrior::kUniform;
  p.occupancy_layer = j.value("occupancy_layer", std::string());
  return p;
}

std::string GraphDocument(const g::FurnitureGraph& graph) {
  Json vertices = Json::array(), edges = Json::array();
  const std::size_t k = static_cast<std::size_t>(graph.category_count);
  for (std::size_t i = 0; i < graph.vertices.size(); ++i) {
    const g::Vertex& v = graph.vertices[i];
    std::vector<double> pf(graph.initial.category.begin() + static_cast<std::ptrdiff_t>(i * k),
                           graph.initial.category.begin() + static_cast<std::ptrdiff_t>((i + 1) * k));
    std::vector<double> po(graph.initial.orientation.begin() + static_cast<std::ptrdiff_t>(i * g::kOrientationCount),
                           graph.initial.orientation.begin() + static_cast<std::ptrdiff_t>((i + 1) * g::kOrientationCount));
    vertices.push_back({{"id", v.id}, {"position", Vec(v.position_m)}, {"extent", Vec(v.extent_m)}, {"yaw_rad", v.yaw_rad},
                        {"categories", pf}, {"orientations", po}});
  }
  for (const g::Edge& e : graph.edges) {
    edges.push_back({{"a", e.a}, {"b", e.b}, {"gap_m", e.gap_m}, {"visual", {e.visual[0], e.visual[1]}}});
  }
  return Json{{"category_count", graph.category_count}, {"vertices", vertices}, {"edges", edges}}.dump();
}

g::FurnitureGraph GraphFromDocument(const std::string& text) {
  const Json j = Json::parse(text);
  g::FurnitureGraph graph;
  graph.category_count = j.at("category_count").get<int>();
  for (const Json& v : j.at("vertices")) {
    graph.vertices.push_back({v.at("id").get<std::string>(), AsVec(v.at("position")), AsVec(v.at("extent")), v.at("yaw_rad").get<double>()});
    const auto pf = v.at("categories").get<std::vector<double>>();
    if (static_cast<int>(pf.size()) != graph.category_count) throw Error(ErrorCode::kInternal, "stored graph is inconsistent");
    graph.initial.category.insert(graph.initial.category.end(), pf.begin(), pf.end());
    // Graphs stored before issue 17 started from the uniform p(o) and do not store it.
    const auto po = v.contains("orientations") ? v.at("orientations").get<std::vector<double>>()
                                               : std::vector<double>(g::kOrientationCount, 1.0 / g::kOrientationCount);
    if (po.size() != g::kOrientationCount) throw Error(ErrorCode::kInternal, "stored graph is inconsistent");
    graph.initial.orientation.insert(graph.initial.orientation.end(), po.begin(), po.end());
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

std::string KnowledgeDocument(const std::string& text) {
  if (text.empty()) {
    return Json{{"categories", Json::parse(g::DefaultCategoriesJson())}, {"frame_prior", Json::parse(g::DefaultFramePriorJson())}}.dump();
  }
  const g::Knowledge check = g::LoadKnowledge(text);  // throws naming the bad entry
  (void)check;
  Json doc = Json::parse(text);
  if (!doc.contains("categories")) doc["categories"] = Json::parse(g::DefaultCategoriesJson());
  if (!doc.contains("frame_prior")) doc["frame_prior"] = Json::parse(g::DefaultFramePriorJson());
  return doc.dump();
}

std::string DescriptionDocument(const DescriptionRequest& request) {
  if (request.text) return Json{{"text", *request.text}}.dump();
  return Json{{"located", request.located}, {"relation", request.relation}, {"reference", request.reference}}.dump();
}

DescriptionRequest DescriptionFromDocument(const std::string& text) {
  const Json j = Json::parse(text);
  DescriptionRequest d;
  if (j.contains("text")) {
    d.text = j.at("text").get<std::string>();
  } else {
    d.located = j.at("located").get<std::string>();
    d.relation = j.at("relation").get<std::string>();
    d.reference = j.at("reference").get<std::string>();
  }
  return d;
}

}  // namespace anchordb::services::furniture_detail
