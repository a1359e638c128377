#pragma once
// Internal to api/furniture_*.cc: the in-memory state of a furniture graph, its typed params, and the helpers the
// service's files share (request parsing and the stored form of a graph live in furniture_graph_json.cc).
#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include "services/furniture/furniture_service.h"
#include "schema/error.h"

namespace anchordb::services {

namespace g = engine::grounding;

namespace furniture_detail {

[[noreturn]] inline void BadArgument(const std::string& message, const std::string& field) {
  throw Error(ErrorCode::kInvalidArgument, message, field);
}

inline Json Vec(const Eigen::Vector2d& v) { return Json::array({v.x(), v.y()}); }

inline int Argmax(const double* p, int n) { return static_cast<int>(std::max_element(p, p + n) - p); }

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

// Requests and the stored form (furniture_graph_json.cc). Parsing throws Error naming the offending field.
g::Viewpoint ParseViewpoint(const Json& j);
Json ViewpointJson(const g::Viewpoint& v);
std::vector<g::FurnitureInput> ParseFurniture(const Json& j, const g::CategoryTable& table, int max_furniture);
GraphConfig ParseConfig(const Json* j, const FurnitureSettings& s);
GraphConfig ConfigFromStored(const Json& j);
// The graph as built, stored whole so that a later change of the building code cannot change a live conversation.
Json GraphJson(const g::FurnitureGraph& graph);
g::FurnitureGraph GraphFromJson(const Json& j);
// The knowledge document new graphs are created with: `text` checked and completed with the built-in tables.
Json KnowledgeDocument(const std::string& text);

}  // namespace furniture_detail

struct FurnitureService::Graph {
  std::mutex mutex;
  storage::FurnitureGraphRecord record;  // hypotheses blob not kept here
  g::FurnitureGraph graph;
  g::Knowledge knowledge;
  furniture_detail::GraphConfig config;
  g::Viewpoint viewpoint;
  g::HypothesisSet set;
};

}  // namespace anchordb::services
