// The checks of the furniture service's typed requests: parameters in range, furniture pieces with their category
// words resolved in the graph's knowledge, descriptions understood. Each throws Error naming the field.
#include <set>

#include "services/furniture/furniture_service_internal.h"
#include "engine/grounding/parser.h"
#include "engine/grounding/readings.h"

namespace anchordb::services::furniture_detail {

namespace {

void CheckRange(double v, double lo, double hi, const std::string& name, const std::string& unit = "") {
  if (v < lo || v > hi) {
    throw Error(ErrorCode::kUnprocessable, name + " must be in [" + std::to_string(static_cast<int>(lo)) + ", " +
                                               std::to_string(static_cast<int>(hi)) + "]" + unit, "params." + name);
  }
}

// p(f) of a piece: weights by category word or id of the table, non-negative, normalised here.
std::vector<double> ResolveCategories(const std::vector<CategoryWeight>& weights, const g::CategoryTable& table,
                                      const std::string& field) {
  std::vector<double> p(static_cast<std::size_t>(table.size()), 0.0);
  double sum = 0.0;
  for (const CategoryWeight& w : weights) {
    const int c = g::ParseCategory(w.word, table, field + "." + w.word);
    if (w.weight < 0.0) throw Error(ErrorCode::kUnprocessable, "category probabilities must not be negative", field + "." + w.word);
    p[static_cast<std::size_t>(c)] += w.weight;
    sum += w.weight;
  }
  if (!(sum > 0.0)) throw Error(ErrorCode::kUnprocessable, "category probabilities must not all be zero", field);
  for (double& v : p) v /= sum;
  return p;
}

}  // namespace

FurnitureGraphParams ResolveParams(const GraphParamsRequest& r, const FurnitureSettings& s) {
  FurnitureGraphParams p;
  p.model = r.model.value_or(s.model == "joint" ? g::Model::kJoint : g::Model::kSequential);
  const std::int64_t n_best = r.n_best.value_or(s.n_best);
  if (n_best < 1 || n_best > s.max_n_best) {
    throw Error(ErrorCode::kUnprocessable, "n_best must be in [1, " + std::to_string(s.max_n_best) + "]", "params.n_best");
  }
  p.n_best = static_cast<int>(n_best);
  p.sigma = r.sigma.value_or(s.sigma);
  CheckRange(p.sigma, 1.0, 1000.0, "sigma");
  p.edge_max_gap_m = r.edge_max_gap_m.value_or(s.edge_max_gap_m);
  CheckRange(p.edge_max_gap_m, 0.0, 100.0, "edge_max_gap_m", " m");
  p.relation_sharpness = r.relation_sharpness.value_or(s.relation_sharpness);
  CheckRange(p.relation_sharpness, 0.0, 100.0, "relation_sharpness");
  p.adaptation = r.adaptation.value_or(true);
  p.frame_prior = r.frame_prior.value_or(FramePrior::kStatistical);
  p.ambiguity_margin = r.ambiguity_margin.value_or(p.model == g::Model::kJoint ? s.ambiguity_margin_joint : s.ambiguity_margin);
  CheckRange(p.ambiguity_margin, 0.0, 10.0, "ambiguity_margin");
  p.category_floor = r.category_floor.value_or(s.category_floor);
  CheckRange(p.category_floor, 0.0, 1.0, "category_floor");
  p.orientation_prior = r.orientation_prior.value_or(OrientationPrior::kRoom);
  p.occupancy_layer = r.occupancy_layer.value_or("");
  return p;
}

g::GroundingParams GroundingParamsOf(const FurnitureGraphParams& params) {
  g::GroundingParams p;
  p.model = params.model;
  p.n_best = params.n_best;
  p.sigma = params.sigma;
  p.schemes = g::SchemesToTry(params.adaptation, params.frame_prior == FramePrior::kUniform);
  p.ambiguity_margin = params.ambiguity_margin;
  p.category_floor = params.category_floor;
  return p;
}

std::vector<g::FurnitureInput> ResolveFurniture(const std::vector<FurniturePieceRequest>& pieces,
                                                const g::CategoryTable& table, int max_furniture) {
  if (static_cast<int>(pieces.size()) > max_furniture) {
    throw Error(ErrorCode::kPayloadTooLarge, "at most " + std::to_string(max_furniture) + " furniture pieces per graph", "furniture");
  }
  std::vector<g::FurnitureInput> out;
  std::set<std::string> ids;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const std::string f = "furniture[" + std::to_string(i) + "]";
    const FurniturePieceRequest& piece = pieces[i];
    g::FurnitureInput in;
    if (piece.id) {
      in.id = *piece.id;
    } else {
      in.id = std::to_string(i + 1);
      in.id.insert(in.id.begin(), 'v');  // not "v" + ...: GCC 12 -O3 raises a false -Wrestrict on that form
    }
    if (!ids.insert(in.id).second) throw Error(ErrorCode::kConflict, "furniture id '" + in.id + "' is given twice", f + ".id");
    in.position_m = piece.position_m;
    in.extent_m = piece.extent_m;
    if (in.extent_m.minCoeff() < 0.0) throw Error(ErrorCode::kUnprocessable, "extent must not be negative", f + ".extent");
    in.yaw_rad = piece.yaw_rad;
    in.category = ResolveCategories(piece.categories, table, f + ".categories");
    out.push_back(std::move(in));
  }
  return out;
}

ResolvedDescription ResolveDescription(const DescriptionRequest& request, const g::CategoryTable& table) {
  ResolvedDescription out;
  if (request.text) {
    const g::ParsedDescription p = g::ParseSentence(*request.text, table, "text");
    out.description = p.description;
    out.understood.words = Understood::Words{p.located_words, p.relation_words, p.reference_words};
  } else {
    out.description.located = g::ParseCategory(request.located, table, "located");
    out.description.relation = g::ParseRelation(request.relation, "relation");
    out.description.reference = g::ParseCategory(request.reference, table, "reference");
  }
  out.understood.located = table[out.description.located].id;
  out.understood.relation = g::RelationId(out.description.relation);
  out.understood.reference = table[out.description.reference].id;
  return out;
}

}  // namespace anchordb::services::furniture_detail
