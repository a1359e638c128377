#pragma once
// Typed requests and results of FurnitureService (thesis 5.3). Positions are in the map frame M [m] (planar);
// relations are those seen from the graph's viewpoint (engine/grounding/knowledge.h); categories are named by their
// id in the knowledge table the graph was created with. Distributions indexed by an engine enum are std::arrays in
// the enum's order.
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::services {

enum class FramePrior { kStatistical, kUniform };
// The initial p(o): from the room (engine/grounding/orientation_prior.h) or uniform (the thesis).
enum class OrientationPrior { kRoom, kUniform };

// The parameters a graph was created with (defaults: FurnitureSettings).
struct FurnitureGraphParams {
  // How hypotheses are scored (engine/grounding/grounding.h Model); graphs stored before it existed: kSequential.
  engine::grounding::Model model = engine::grounding::Model::kSequential;
  int n_best = 100;                 // hypotheses kept per description
  double sigma = 3.0;               // damping of eq. 5.4
  double edge_max_gap_m = 1.5;      // pieces closer than this share an edge [m]
  double relation_sharpness = 3.0;  // kappa of the initial p(r)
  bool adaptation = true;           // also the relative- and intrinsic-preferring schemes (5.3.4)
  FramePrior frame_prior = FramePrior::kStatistical;
  // Ambiguity (engine/grounding/ambiguity.h): readings of other pieces within this much accumulated score of the
  // best make a description ambiguous and hold its category update back; 0 = off (graphs stored before issue 17).
  // Units of the model's score: S of eq. 5.2 (sequential), nats (joint).
  double ambiguity_margin = 0.0;
  // A piece's p(f) moves only towards a category it holds with at least this probability; 0 = always.
  double category_floor = 0.0;
  OrientationPrior orientation_prior = OrientationPrior::kUniform;  // graphs stored before issue 17: uniform
  std::string occupancy_layer;  // the map's occupancy layer the room prior finds walls in ("" = none)
};

// Requested parameters; an unset one takes the service's setting. Out of range: Error(kUnprocessable) naming
// "params.<name>".
struct GraphParamsRequest {
  std::optional<engine::grounding::Model> model;  // default: the grounding_model setting
  std::optional<std::int64_t> n_best;        // [1, max_n_best]
  std::optional<double> sigma;               // [1, 1000]
  std::optional<double> edge_max_gap_m;      // [0, 100] m
  std::optional<double> relation_sharpness;  // [0, 100]
  std::optional<bool> adaptation;
  std::optional<FramePrior> frame_prior;
  std::optional<double> ambiguity_margin;  // [0, 10]; default by model: the setting for S or for nats
  std::optional<double> category_floor;    // [0, 1]
  std::optional<OrientationPrior> orientation_prior;  // default kRoom
  std::optional<std::string> occupancy_layer;         // an occupancy layer of the map; unknown: kNotFound
};

// A category word (or id) of the knowledge table and its weight (>= 0; the weights of a piece are normalised).
struct CategoryWeight {
  std::string word;
  double weight = 0.0;
};

struct FurniturePieceRequest {
  std::optional<std::string> id;                          // unique in the graph; default "v<position in the list + 1>"
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();   // footprint centre in M [m]
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();     // footprint size along its own axes [m], >= 0
  double yaw_rad = 0.0;                                   // footprint rotation in M [rad]
  std::vector<CategoryWeight> categories;                 // p(f) before normalisation; not all zero
};

struct CreateGraphRequest {
  engine::grounding::Viewpoint viewpoint;      // where the furniture is seen from (M)
  std::vector<FurniturePieceRequest> furniture;  // at least two pieces with an edge; at most max_furniture
  GraphParamsRequest params;
  // Instead of `furniture`: the map's furniture instances (found by segmentation or entered by an operator), each
  // with its p(f) over the categories of the knowledge table (labels that are no category word are left out; an
  // instance with none is left out), footprint and yaw; vertex ids "f<instance id>".
  bool from_instances = false;
};

// One spoken description: a sentence, or the three words (category word, relation word or id, category word).
struct DescriptionRequest {
  std::optional<std::string> text;
  std::string located, relation, reference;  // used when text is absent
};

struct ProduceRequest {
  std::string located;    // vertex ids of the graph
  std::string reference;
};

struct CategoryProbability {
  std::string category;  // id
  double probability = 0.0;
};

struct VertexView {
  std::string id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  std::string label;  // category id of largest p(f)
  double label_probability = 0.0;
  std::vector<CategoryProbability> categories;         // p(f), one per category of the graph's table
  std::optional<engine::grounding::Orientation> front;  // none while p(o) singles out no orientation
  engine::grounding::Distribution4 orientations{};     // p(o)
};

struct EdgeView {
  std::string a, b;  // vertex ids
  double gap_m = 0.0;
  engine::grounding::Distribution4 a_relative_to_b{}, b_relative_to_a{};                // p(r), best hypothesis
  engine::grounding::Distribution4 visual_a_relative_to_b{}, visual_b_relative_to_a{};  // p(r) from the geometry
};

// A grounded description: which pieces, which frame (and the reference's front for the intrinsic frame), and the
// relation as seen from the viewpoint.
struct MatchView {
  std::string located, reference;  // vertex ids
  engine::grounding::Frame frame = engine::grounding::Frame::kRelative;
  engine::grounding::Relation relation_seen = engine::grounding::Relation::kLeftOf;
  engine::grounding::Scheme scheme = engine::grounding::Scheme::kStatistical;
  double score = 0.0;
  std::optional<engine::grounding::Orientation> reference_front;  // intrinsic frame only
};

// What a description was understood as: category ids and the relation id; for a sentence also the words spoken.
struct Understood {
  std::string located, relation, reference;
  struct Words {
    std::string located, relation, reference;
  };
  std::optional<Words> words;
};

struct GroundedDescription {
  int seq = 0;  // 1 = the first description
  MatchView match;
  std::optional<DescriptionRequest> input;  // as given, with what it was understood as (when stored)
  std::optional<Understood> understood;
};

// A competing reading of an ambiguous (or poorly fitting) description.
struct AlternativeView {
  MatchView match;
  double total = 0.0;  // accumulated score of the best hypothesis reading it so
  std::string phrase;  // how the robot tells this reading's piece apart: "the table to the left of the sofa"
};

// A description the memory is not sure about: its competing readings and the question the dialog can ask back.
struct AmbiguityView {
  int seq = 0;              // the description (1 = the first)
  bool ambiguous = false;   // readings of different pieces are within the margin: its category update is held back
  bool poor = false;        // the best reading names a category its piece holds below category_floor
  std::vector<AlternativeView> alternatives;  // best first
  std::string question;     // "do you mean the table to the left of the sofa or the table behind the shelf?"
};

// An explicit answer to a question: which pieces description `seq` meant (the oldest held one when absent).
struct ResolveRequest {
  std::optional<std::int64_t> seq;
  std::string located, reference;  // vertex ids
};

struct BestHypothesis {
  std::int64_t hypothesis = 0;
  std::optional<engine::grounding::Scheme> scheme;  // none for G0
  double score = 0.0;
};

// The graph under its best hypothesis.
struct GraphView {
  std::int64_t id = 0;
  std::string map;
  engine::grounding::Viewpoint viewpoint;
  FurnitureGraphParams params;
  std::int64_t created_ns = 0, updated_ns = 0;
  int descriptions = 0;          // grounded so far
  std::size_t hypotheses = 0;    // live
  BestHypothesis best;
  std::vector<VertexView> vertices;
  std::vector<EdgeView> edges;
  std::vector<GroundedDescription> groundings;  // the best sequence, oldest first
  std::vector<AmbiguityView> pending;            // held (ambiguous) descriptions awaiting a resolution, oldest first
};

struct GraphSummary {
  std::int64_t id = 0;
  engine::grounding::Viewpoint viewpoint;
  FurnitureGraphParams params;
  std::int64_t descriptions = 0;
  std::int64_t created_ns = 0, updated_ns = 0;
};

struct GroundingResult {
  std::int64_t graph = 0;
  int seq = 0;
  Understood understood;
  MatchView match;  // of this description in the best sequence
  BestHypothesis best;
  std::vector<int> ancestor_ranks;  // of the best hypothesis, per step
  bool revised = false;             // the best sequence left the previous best (figures 5.9-5.10)
  std::vector<MatchView> groundings;
  std::size_t hypotheses = 0;
  std::optional<AmbiguityView> ambiguity;  // when this description is ambiguous or fits poorly
  std::vector<int> settled;                // earlier held descriptions (seq) this one settled
};

struct VertexLabel {
  std::string vertex;
  std::string category;
};

struct HypothesisView {
  int rank = 1;  // 1 = best
  std::int64_t id = 0;
  std::optional<std::int64_t> parent;  // none for G0
  std::optional<engine::grounding::Scheme> scheme;
  double score = 0.0;
  std::vector<int> ancestor_ranks;
  std::optional<MatchView> last_match;
  std::vector<VertexLabel> labels;
};

struct HypothesisList {
  std::int64_t graph = 0;
  int descriptions = 0;
  std::size_t count = 0;  // live hypotheses (the list holds at most the limit asked for)
  std::vector<HypothesisView> hypotheses;
};

// How this listener most likely names two pieces and their relation (5.3.5).
struct NamedPiece {
  std::string vertex, label, name;  // vertex id, category id, the word said
  double probability = 0.0;         // p(label)
};

struct WordProbability {
  engine::grounding::Relation relation = engine::grounding::Relation::kLeftOf;
  double probability = 0.0;
};

struct Utterance {
  NamedPiece located, reference;
  engine::grounding::Relation relation = engine::grounding::Relation::kLeftOf;
  engine::grounding::Frame frame = engine::grounding::Frame::kRelative;
  double probability = 0.0;                   // of the word said
  std::vector<WordProbability> alternatives;  // every word, most probable first
  engine::grounding::Scheme scheme = engine::grounding::Scheme::kStatistical;
  std::string sentence;                       // "the shelf is to the right of the sofa"
};

}  // namespace anchordb::services
