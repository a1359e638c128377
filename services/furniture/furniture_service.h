#pragma once
// Furniture graphs and the grounding of spoken spatial descriptions (thesis 5.3), behind the /furniture-graphs
// routes. A graph is built from furniture seen from a viewpoint; every description is grounded against the live
// n-best hypotheses, and the new set is written to the database (with the description) before the call returns,
// so a restarted server continues a conversation exactly where it stopped. Bad input (unknown words, a relation
// outside the vocabulary, a sentence that does not parse) is refused with anchordb::Error naming the field before
// anything changes; an unknown map or graph is kNotFound.
#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "schema/clock.h"
#include "services/furniture/furniture_types.h"
#include "services/furniture/placement.h"
#include "storage/furniture_repository.h"
#include "storage/store.h"

namespace anchordb::services {

struct FurnitureSettings {
  int n_best = 100;                  // hypotheses kept per description (default of a graph's params.n_best)
  int max_n_best = 2000;             // largest params.n_best accepted
  double sigma = 3.0;                // damping of eq. 5.4 (>= 1; 1 = the description replaces the belief)
  double edge_max_gap_m = 1.5;       // pieces closer than this share an edge [m]
  double relation_sharpness = 3.0;   // kappa of the initial p(r) by angle
  std::string model = "joint";     // default of params.model: "joint" (joint_model.h) or "sequential" (the thesis')
  double ambiguity_margin = 0.02;    // default of params.ambiguity_margin for the sequential model (units of S, eq. 5.2)
  double ambiguity_margin_joint = 0.3;  // the same for the joint model [nats]
  double category_floor = 0.05;      // default of params.category_floor (half the chance level of the 10 default categories)
  int max_furniture = 64;            // pieces per graph
  std::size_t max_text_length = 500; // characters of a spoken description
  // The grounding knowledge document ({"categories": ..., "frame_prior": ...}, either may be missing); empty = the
  // tables built in (engine/grounding/*.json). Each graph keeps a copy of the tables it was created with.
  std::string knowledge_json;
};

class FurnitureService {
 public:
  // Throws Error(kInvalidArgument) when settings.knowledge_json does not load.
  FurnitureService(storage::Store& store, FurnitureSettings settings, const Clock& clock = SystemClock::Instance());

  // Builds a graph (G0 = the graph as seen). Unknown category words: kUnprocessable naming
  // "furniture[i].categories.<word>"; too many pieces: kPayloadTooLarge; a repeated id: kConflict.
  GraphView Create(const std::string& map, const CreateGraphRequest& request);
  // Graphs of the map with id < before_id (0 = from the newest), newest first, at most `limit`.
  std::vector<GraphSummary> List(const std::string& map, std::int64_t before_id, int limit);
  GraphView Get(const std::string& map, std::int64_t id);
  // Grounds one description and stores the new hypotheses; a word or sentence not understood: kUnprocessable
  // naming "text", "located", "relation" or "reference".
  GroundingResult Describe(const std::string& map, std::int64_t id, const DescriptionRequest& request);
  // The live hypotheses, best first, at most `limit`.
  HypothesisList Hypotheses(const std::string& map, std::int64_t id, int limit);
  // Settles a held description by naming its pieces. Unknown vertex kNotFound; no held description (or `seq` not
  // held) kConflict; no live reading of the description with that pair kUnprocessable. Nothing changes on error.
  GraphView Resolve(const std::string& map, std::int64_t id, const ResolveRequest& request);
  // Forgets the descriptions: back to G0.
  GraphView Reset(const std::string& map, std::int64_t id);
  // Speech production: unknown vertex kNotFound; two pieces without an edge or the same piece kUnprocessable.
  Utterance Produce(const std::string& map, std::int64_t id, const ProduceRequest& request);

  // Where a thing at p_map (map frame [m]) stands relative to the furniture of the map's newest graph, in the words
  // the grounding model of that graph's listener prefers (SPEC §4.4). Nullopt when the map has no furniture graph.
  // `graph`: the graph to use when the caller already knows the newest one (saves a database read).
  std::optional<Placement> Place(const std::string& map, const Eigen::Vector3d& p_map, std::optional<std::int64_t> graph = {});

  const FurnitureSettings& settings() const { return settings_; }
  // The knowledge document new graphs are created with, serialised (JSON text as stored with each graph).
  const std::string& knowledge_json() const { return knowledge_json_; }

  // A graph's in-memory state (services/furniture/furniture_service_internal.h).
  struct Graph;

 private:
  std::shared_ptr<Graph> Acquire(const std::string& map, std::int64_t id);
  GraphView View(const Graph& g, const std::vector<storage::GraphDescriptionRecord>& descriptions) const;

  storage::Store& store_;
  FurnitureSettings settings_;
  const Clock& clock_;
  std::string knowledge_json_;
  std::mutex graphs_mutex_;
  std::map<std::int64_t, std::shared_ptr<Graph>> graphs_;
};

}  // namespace anchordb::services
