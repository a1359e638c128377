#include "api/furniture_json.h"
#include "api/request_limits.h"

#include "schema/error.h"

namespace anchordb::api {

namespace g = engine::grounding;
using namespace anchordb::services;

namespace {

[[noreturn]] void BadArgument(const std::string& message, const std::string& field) {
  throw Error(ErrorCode::kInvalidArgument, message, field);
}

bool Given(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && !it->is_null();
}

// [x, y] or [x, y, z] (z ignored: graphs are planar) with finite numbers.
Eigen::Vector2d AsPlanar(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() < 2 || v.size() > 3) BadArgument(field + " must be [x, y] or [x, y, z] in metres", field);
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) out[i] = json::AsFiniteNumber(v[static_cast<std::size_t>(i)], field);
  if (v.size() == 3) json::AsFiniteNumber(v[2], field);
  return out;
}

g::Viewpoint ParseViewpoint(const Json& j) {
  if (!j.is_object()) BadArgument("viewpoint must be an object {position:[x,y], heading_rad}", "viewpoint");
  json::RejectUnknownKeys(j, {"position", "heading_rad"}, "viewpoint");
  g::Viewpoint v;
  v.position_m = AsPlanar(json::Require(j, "position", "viewpoint"), "viewpoint.position");
  v.heading_rad = json::RequireFiniteNumber(j, "heading_rad", "viewpoint");
  return v;
}

GraphParamsRequest ParseParams(const Json& j) {
  if (!j.is_object()) BadArgument("params must be an object", "params");
  json::RejectUnknownKeys(j, {"model", "n_best", "sigma", "edge_max_gap_m", "relation_sharpness", "adaptation", "frame_prior",
                              "ambiguity_margin", "category_floor", "orientation_prior", "occupancy_layer"}, "params");
  GraphParamsRequest p;
  if (const auto model = json::OptionalString(j, "model", limits::kWordLength, "params")) {
    if (*model == "joint") p.model = g::Model::kJoint;
    else if (*model == "sequential") p.model = g::Model::kSequential;
    else BadArgument("model must be sequential or joint", "params.model");
  }
  if (Given(j, "n_best")) p.n_best = json::IntegerOr(j, "n_best", 0, "params");
  if (Given(j, "sigma")) p.sigma = json::FiniteNumberOr(j, "sigma", 0.0, "params");
  if (Given(j, "edge_max_gap_m")) p.edge_max_gap_m = json::FiniteNumberOr(j, "edge_max_gap_m", 0.0, "params");
  if (Given(j, "relation_sharpness")) p.relation_sharpness = json::FiniteNumberOr(j, "relation_sharpness", 0.0, "params");
  if (Given(j, "ambiguity_margin")) p.ambiguity_margin = json::FiniteNumberOr(j, "ambiguity_margin", 0.0, "params");
  if (Given(j, "category_floor")) p.category_floor = json::FiniteNumberOr(j, "category_floor", 0.0, "params");
  if (const auto prior = json::OptionalString(j, "orientation_prior", limits::kWordLength, "params")) {
    if (*prior == "room") p.orientation_prior = OrientationPrior::kRoom;
    else if (*prior == "uniform") p.orientation_prior = OrientationPrior::kUniform;
    else BadArgument("orientation_prior must be room or uniform", "params.orientation_prior");
  }
  if (Given(j, "occupancy_layer")) p.occupancy_layer = json::RequireId(j, "occupancy_layer", "params");
  if (Given(j, "adaptation")) p.adaptation = json::BoolOr(j, "adaptation", true, "params");
  if (const auto prior = json::OptionalString(j, "frame_prior", limits::kWordLength, "params")) {
    if (*prior == "statistical") p.frame_prior = FramePrior::kStatistical;
    else if (*prior == "uniform") p.frame_prior = FramePrior::kUniform;
    else BadArgument("frame_prior must be statistical or uniform", "params.frame_prior");
  }
  return p;
}

// {"sofa": 0.7, "armchair": 0.2, ...}: category words (resolved by the service) and finite weights.
std::vector<CategoryWeight> ParseCategories(const Json& j, const std::string& field) {
  if (!j.is_object() || j.empty()) {
    BadArgument(field + " must be an object of category probabilities, e.g. {\"sofa\": 0.7, \"armchair\": 0.3}", field);
  }
  limits::CheckItems(j, limits::kCategoriesPerPiece, field);
  std::vector<CategoryWeight> out;
  for (const auto& [word, value] : j.items()) {
    limits::CheckLength(word, limits::kCategoryWordLength, field);
    out.push_back({word, json::AsFiniteNumber(value, field + "." + word)});
  }
  return out;
}

std::vector<FurniturePieceRequest> ParseFurniture(const Json& j) {
  if (!j.is_array()) BadArgument("furniture must be an array of pieces", "furniture");
  std::vector<FurniturePieceRequest> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string f = "furniture[" + std::to_string(i) + "]";
    const Json& piece = j[i];
    if (!piece.is_object()) BadArgument(f + " must be an object", f);
    json::RejectUnknownKeys(piece, {"id", "position", "extent", "yaw_rad", "categories"}, f);
    FurniturePieceRequest in;
    if (piece.contains("id")) in.id = json::RequireId(piece, "id", f);
    in.position_m = AsPlanar(json::Require(piece, "position", f), f + ".position");
    if (piece.contains("extent")) in.extent_m = AsPlanar(piece["extent"], f + ".extent");
    in.yaw_rad = json::FiniteNumberOr(piece, "yaw_rad", 0.0, f);
    in.categories = ParseCategories(json::Require(piece, "categories", f), f + ".categories");
    out.push_back(std::move(in));
  }
  return out;
}

Json Vec(const Eigen::Vector2d& v) { return Json::array({v.x(), v.y()}); }

Json ViewpointJson(const g::Viewpoint& v) { return {{"position", Vec(v.position_m)}, {"heading_rad", v.heading_rad}}; }

Json ParamsJson(const FurnitureGraphParams& p) {
  return {{"model", g::ModelId(p.model)}, {"n_best", p.n_best}, {"sigma", p.sigma}, {"edge_max_gap_m", p.edge_max_gap_m}, {"relation_sharpness", p.relation_sharpness},
          {"adaptation", p.adaptation}, {"frame_prior", p.frame_prior == FramePrior::kUniform ? "uniform" : "statistical"},
          {"ambiguity_margin", p.ambiguity_margin}, {"category_floor", p.category_floor},
          {"orientation_prior", p.orientation_prior == OrientationPrior::kRoom ? "room" : "uniform"},
          {"occupancy_layer", p.occupancy_layer.empty() ? Json(nullptr) : Json(p.occupancy_layer)}};
}

std::string SchemeName(const std::optional<g::Scheme>& s) { return s ? g::SchemeId(*s) : "none"; }

Json RelationDistribution(const g::Distribution4& p) {
  Json out = Json::object();
  for (int r = 0; r < g::kRelationCount; ++r) out[g::RelationId(static_cast<g::Relation>(r))] = p[static_cast<std::size_t>(r)];
  return out;
}

Json MatchJson(const MatchView& m) {
  return {{"located", m.located},
          {"reference", m.reference},
          {"frame", g::FrameId(m.frame)},
          {"relation_seen", g::RelationId(m.relation_seen)},
          {"scheme", g::SchemeId(m.scheme)},
          {"score", m.score},
          {"reference_front", m.reference_front ? Json(g::OrientationId(*m.reference_front)) : Json(nullptr)}};
}

Json DescriptionJson(const DescriptionRequest& d) {
  if (d.text) return {{"text", *d.text}};
  return {{"located", d.located}, {"relation", d.relation}, {"reference", d.reference}};
}

Json UnderstoodJson(const Understood& u) {
  Json out = {{"located", u.located}, {"relation", u.relation}, {"reference", u.reference}};
  if (u.words) out["words"] = {{"located", u.words->located}, {"relation", u.words->relation}, {"reference", u.words->reference}};
  return out;
}

Json VertexJson(const VertexView& v) {
  Json categories = Json::object(), orientations = Json::object();
  for (const CategoryProbability& c : v.categories) categories[c.category] = c.probability;
  for (int o = 0; o < g::kOrientationCount; ++o) {
    orientations[g::OrientationId(static_cast<g::Orientation>(o))] = v.orientations[static_cast<std::size_t>(o)];
  }
  return {{"id", v.id},
          {"position", Vec(v.position_m)},
          {"extent", Vec(v.extent_m)},
          {"yaw_rad", v.yaw_rad},
          {"label", v.label},
          {"label_probability", v.label_probability},
          {"categories", categories},
          {"front", v.front ? Json(g::OrientationId(*v.front)) : Json(nullptr)},
          {"orientations", orientations}};
}

Json EdgeJson(const EdgeView& e) {
  return {{"a", e.a},
          {"b", e.b},
          {"gap_m", e.gap_m},
          {"a_relative_to_b", RelationDistribution(e.a_relative_to_b)},
          {"b_relative_to_a", RelationDistribution(e.b_relative_to_a)},
          {"visual", {{"a_relative_to_b", RelationDistribution(e.visual_a_relative_to_b)},
                      {"b_relative_to_a", RelationDistribution(e.visual_b_relative_to_a)}}}};
}

Json AmbiguityJson(const AmbiguityView& a) {
  Json alternatives = Json::array();
  for (const AlternativeView& alt : a.alternatives) {
    Json item = MatchJson(alt.match);
    item["total"] = alt.total;
    item["phrase"] = alt.phrase;
    alternatives.push_back(item);
  }
  return {{"seq", a.seq}, {"ambiguous", a.ambiguous}, {"poor", a.poor}, {"alternatives", alternatives}, {"question", a.question}};
}

Json NamedPieceJson(const NamedPiece& p) {
  return {{"vertex", p.vertex}, {"label", p.label}, {"name", p.name}, {"probability", p.probability}};
}

}  // namespace

CreateGraphRequest ParseCreateGraph(const Json& body) {
  json::RejectUnknownKeys(body, {"viewpoint", "furniture", "params", "from_instances"});
  CreateGraphRequest out;
  out.viewpoint = ParseViewpoint(json::Require(body, "viewpoint"));
  if (body.contains("params")) out.params = ParseParams(body["params"]);
  if (body.contains("from_instances")) {
    if (!body["from_instances"].is_boolean()) BadArgument("from_instances must be true or false", "from_instances");
    out.from_instances = body["from_instances"].get<bool>();
  }
  if (out.from_instances) {
    if (body.contains("furniture")) BadArgument("give furniture or from_instances, not both", "furniture");
    return out;
  }
  out.furniture = ParseFurniture(json::Require(body, "furniture"));
  return out;
}

DescriptionRequest ParseDescription(const Json& body, std::size_t max_text_length) {
  json::RejectUnknownKeys(body, {"text", "located", "relation", "reference"});
  DescriptionRequest out;
  if (body.contains("text")) {
    if (body.contains("located") || body.contains("relation") || body.contains("reference")) {
      BadArgument("give either text or located, relation and reference, not both", "text");
    }
    out.text = json::RequireString(body, "text", max_text_length);
    return out;
  }
  out.located = json::RequireString(body, "located", limits::kDescriptionWordLength);
  out.relation = json::RequireString(body, "relation", limits::kDescriptionWordLength);
  out.reference = json::RequireString(body, "reference", limits::kDescriptionWordLength);
  return out;
}

ResolveRequest ParseResolve(const Json& body) {
  json::RejectUnknownKeys(body, {"seq", "located", "reference"});
  ResolveRequest out;
  if (Given(body, "seq")) out.seq = json::IntegerOr(body, "seq", 0, "");
  out.located = json::RequireString(body, "located", limits::kDescriptionWordLength);
  out.reference = json::RequireString(body, "reference", limits::kDescriptionWordLength);
  return out;
}

ProduceRequest ParseProduce(const Json& body) {
  json::RejectUnknownKeys(body, {"located", "reference"});
  ProduceRequest out;
  out.located = json::RequireString(body, "located", limits::kDescriptionWordLength);
  out.reference = json::RequireString(body, "reference", limits::kDescriptionWordLength);
  return out;
}

Json ToJson(const GraphView& view) {
  Json vertices = Json::array(), edges = Json::array(), groundings = Json::array();
  for (const VertexView& v : view.vertices) vertices.push_back(VertexJson(v));
  for (const EdgeView& e : view.edges) edges.push_back(EdgeJson(e));
  for (const GroundedDescription& d : view.groundings) {
    Json item = MatchJson(d.match);
    item["seq"] = d.seq;
    if (d.input) item["input"] = DescriptionJson(*d.input);
    if (d.understood) item["understood"] = UnderstoodJson(*d.understood);
    groundings.push_back(item);
  }
  return {{"id", view.id},
          {"map", view.map},
          {"viewpoint", ViewpointJson(view.viewpoint)},
          {"params", ParamsJson(view.params)},
          {"created_ns", view.created_ns},
          {"updated_ns", view.updated_ns},
          {"descriptions", view.descriptions},
          {"hypotheses", view.hypotheses},
          {"best", {{"hypothesis", view.best.hypothesis}, {"scheme", SchemeName(view.best.scheme)}, {"score", view.best.score}}},
          {"vertices", vertices},
          {"edges", edges},
          {"groundings", groundings},
          {"pending", [&] {
             Json pending = Json::array();
             for (const AmbiguityView& p : view.pending) pending.push_back(AmbiguityJson(p));
             return pending;
           }()}};
}

Json ToJson(const std::vector<GraphSummary>& graphs) {
  Json list = Json::array();
  for (const GraphSummary& r : graphs) {
    list.push_back({{"id", r.id}, {"viewpoint", ViewpointJson(r.viewpoint)}, {"params", ParamsJson(r.params)},
                    {"descriptions", r.descriptions}, {"created_ns", r.created_ns}, {"updated_ns", r.updated_ns}});
  }
  return {{"furniture_graphs", list}};
}

Json ToJson(const GroundingResult& r) {
  Json sequence = Json::array();
  for (const MatchView& m : r.groundings) sequence.push_back(MatchJson(m));
  return {{"graph", r.graph},
          {"seq", r.seq},
          {"understood", UnderstoodJson(r.understood)},
          {"match", MatchJson(r.match)},
          {"best", {{"hypothesis", r.best.hypothesis}, {"scheme", SchemeName(r.best.scheme)}, {"score", r.best.score},
                    {"ancestor_ranks", r.ancestor_ranks}, {"revised", r.revised}}},
          {"groundings", sequence},
          {"hypotheses", r.hypotheses},
          {"ambiguity", r.ambiguity ? AmbiguityJson(*r.ambiguity) : Json(nullptr)},
          {"settled", r.settled}};
}

Json ToJson(const HypothesisList& l) {
  Json list = Json::array();
  for (const HypothesisView& h : l.hypotheses) {
    Json labels = Json::object();
    for (const VertexLabel& v : h.labels) labels[v.vertex] = v.category;
    list.push_back({{"rank", h.rank},
                    {"id", h.id},
                    {"parent", h.parent ? Json(*h.parent) : Json(nullptr)},
                    {"scheme", SchemeName(h.scheme)},
                    {"score", h.score},
                    {"ancestor_ranks", h.ancestor_ranks},
                    {"last_match", h.last_match ? MatchJson(*h.last_match) : Json(nullptr)},
                    {"labels", labels}});
  }
  return {{"graph", l.graph}, {"descriptions", l.descriptions}, {"count", l.count}, {"hypotheses", list}};
}

Json ToJson(const Utterance& u) {
  Json alternatives = Json::array();
  for (const WordProbability& w : u.alternatives) alternatives.push_back({{"relation", g::RelationId(w.relation)}, {"probability", w.probability}});
  return {{"located", NamedPieceJson(u.located)},
          {"reference", NamedPieceJson(u.reference)},
          {"relation", g::RelationId(u.relation)},
          {"phrase", g::RelationPhrase(u.relation)},
          {"frame", g::FrameId(u.frame)},
          {"probability", u.probability},
          {"alternatives", alternatives},
          {"scheme", g::SchemeId(u.scheme)},
          {"sentence", u.sentence}};
}

}  // namespace anchordb::api
