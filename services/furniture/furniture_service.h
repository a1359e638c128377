#pragma once
// Furniture graphs and the grounding of spoken spatial descriptions (thesis 5.3), behind the /furniture-graphs
// routes. A graph is built from furniture seen from a viewpoint; every description is grounded against the live
// n-best hypotheses, and the new set is written to the database (with the description) before the call returns,
// so a restarted server continues a conversation exactly where it stopped. Bad input (unknown words, a relation
// outside the vocabulary, a sentence that does not parse) is refused before anything changes.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "engine/grounding/grounding.h"
#include "storage/furniture_repository.h"
#include "storage/repositories.h"
#include "storage/store.h"
#include "services/common/transitional_json.h"

namespace anchordb::services {

struct FurnitureSettings {
  int n_best = 100;                  // hypotheses kept per description (default of a graph's params.n_best)
  int max_n_best = 2000;             // largest params.n_best accepted
  double sigma = 3.0;                // damping of eq. 5.4 (>= 1; 1 = the description replaces the belief)
  double edge_max_gap_m = 1.5;       // pieces closer than this share an edge [m]
  double relation_sharpness = 3.0;   // kappa of the initial p(r) by angle
  int max_furniture = 64;            // pieces per graph
  std::size_t max_text_length = 500; // characters of a spoken description
  // The grounding knowledge document ({"categories": ..., "frame_prior": ...}, either may be missing); empty = the
  // tables built in (engine/grounding/*.json). Each graph keeps a copy of the tables it was created with.
  std::string knowledge_json;
};

class FurnitureService {
 public:
  // Throws Error(kInvalidArgument) when settings.knowledge_json does not load.
  FurnitureService(storage::Store& store, FurnitureSettings settings);

  Json Create(const std::string& map, const Json& body);
  Json List(const std::string& map, std::int64_t before_id, int limit);
  Json Get(const std::string& map, std::int64_t id);
  Json Describe(const std::string& map, std::int64_t id, const Json& body);  // ground one description
  Json Hypotheses(const std::string& map, std::int64_t id, int limit);
  Json Reset(const std::string& map, std::int64_t id);
  Json Produce(const std::string& map, std::int64_t id, const Json& body);   // speech production (:describe)

  // Where a thing at p_M stands relative to the furniture of the map's newest graph, in the words the grounding
  // model of that graph's listener prefers (SPEC §4.4): {graph, furniture, category, name, relation, frame, gap_m,
  // phrase}. Nullopt when the map has no furniture graph.
  // `graph`: the graph to use when the caller already knows the newest one (saves a database read).
  std::optional<Json> Place(const std::string& map, const Eigen::Vector3d& p_M, std::optional<std::int64_t> graph = {});

  // The knowledge new graphs are created with, as a document.
  const Json& knowledge() const { return knowledge_doc_; }

 private:
  struct Graph;
  std::shared_ptr<Graph> Acquire(const std::string& map, std::int64_t id);
  Json View(const Graph& g, const std::vector<storage::GraphDescriptionRecord>& descriptions) const;

  storage::Store& store_;
  FurnitureSettings settings_;
  Json knowledge_doc_;
  std::mutex graphs_mutex_;
  std::map<std::int64_t, std::shared_ptr<Graph>> graphs_;
};

// The codec of the hypotheses blob (exposed for tests): a versioned f64 array.
std::string EncodeHypotheses(const engine::grounding::FurnitureGraph& graph, const engine::grounding::HypothesisSet& set);
engine::grounding::HypothesisSet DecodeHypotheses(const engine::grounding::FurnitureGraph& graph, const std::string& blob);

}  // namespace anchordb::services
