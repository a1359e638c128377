#pragma once
// Grounding of spoken spatial descriptions in a furniture graph (thesis 5.3.2-5.3.5).
//
// A description (located category, relation word, reference category) is matched against every directed edge
// under 5 interpretations: the relative frame, and the intrinsic frame of the reference for each of its 4
// possible orientations (Algorithm 5). Each is scored by eq. 5.2
//   S = (P(f_loc | v_loc) + P(f_ref | v_ref) + P(rho | e)) / 3
// with P(rho | e) of eq. 5.3 = P(r' | e) x P(frame | nature(f_ref), o_ref, r') x P(o_ref | v_ref), where r' is the
// relation in the relative frame that the interpretation gives, maximised over the reference's orientation o as
// eq. 5.3 says (for the relative interpretation r' = r for every o; o still weighs the frame probability).
// Each interpretation is assessed under a scheme of reference-frame use (statistical, relative-preferring,
// intrinsic-preferring; 5.3.4): 15 interpretations per directed edge when adaptation is on.
//
// The n best (graph, match) pairs are kept with their accumulated score and predecessor (5.3.3); a hypothesis
// continues only under the scheme it was first matched with (5.3.4). The chosen match updates p(f) of both
// vertices and p(r) of the directed edge by eq. 5.4 (damping sigma) towards the described category and the
// relation r'; an intrinsic match also pushes p(o) of the reference towards eq. 5.5,
//   p_verbal(o = x) ∝ P_visual(I(r | intrinsic, x) | e),
// the orientations under which the spoken word names the relation seen in the geometry.
//
// Everything is deterministic: equal scores are ordered by (predecessor rank, scheme, edge, interpretation).
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/grounding/furniture_graph.h"
#include "engine/grounding/knowledge.h"

namespace anchordb::engine::grounding {

// Category indices into the knowledge's CategoryTable.
struct Description {
  int located = -1;
  Relation relation = Relation::kLeftOf;
  int reference = -1;
};

// Interpretation index: 0 = relative frame, 1 + o = intrinsic frame with the reference's front at o.
inline constexpr int kInterpretationCount = 5;
inline Frame FrameOf(int interpretation) { return interpretation == 0 ? Frame::kRelative : Frame::kIntrinsic; }
inline Orientation OrientationOf(int interpretation) { return static_cast<Orientation>(interpretation - 1); }

struct InterpretationScore {
  Relation relative = Relation::kLeftOf;  // r' = I(r | frame[, o])
  double rho = 0.0;                       // P(rho | e), eq. 5.3
  double score = 0.0;                     // S, eq. 5.2
};

// The 5 interpretations of `d` on directed edge `directed` of a graph in state `state`, under scheme `s`.
std::array<InterpretationScore, kInterpretationCount> ScoreInterpretations(const FurnitureGraph& graph,
                                                                           const GraphState& state,
                                                                           const Knowledge& knowledge, Scheme s,
                                                                           const Description& d, int directed);

// Eq. 5.4 on one distribution: p += (target - p) / sigma, then normalised. sigma >= 1.
void DampedUpdate(double* p, const double* target, int size, double sigma);

// Eq. 5.5: the orientation target for an intrinsic reading of `word` on directed edge `directed`.
Distribution4 OrientationTarget(const FurnitureGraph& graph, int directed, Relation word, Nature nature);

struct Match {
  int directed_edge = -1;
  int interpretation = 0;                 // see kInterpretationCount
  Relation relative = Relation::kLeftOf;  // r'
  Scheme scheme = Scheme::kStatistical;
  double score = 0.0;                     // S of this step (kSequential), log P(d_t | d_<t) in nats (kJoint)
  int located_category = -1;              // the categories the description named (-1: not recorded)
  int reference_category = -1;
};

// The state after applying `match` of description `d` to `state` (eq. 5.4, 5.5). A poor match - a described
// category below category_floor on its piece that no earlier match of the same hypothesis (`earlier`) named that
// piece with - moves no p(f) at all: one poor match never moves a category belief, a confirmed one does (0 = the
// thesis: always). `categories` = false holds the category half of the update
// back (an ambiguous step).
GraphState ApplyMatch(const FurnitureGraph& graph, const GraphState& state, const Knowledge& knowledge,
                      const Description& d, const Match& match, double sigma, double category_floor = 0.0,
                      bool categories = true, const std::vector<Match>& earlier = {});
// Whether a match may move categories at all: false for a poor match (a described category below category_floor
// on its piece that no match in `earlier` named that piece with).
bool CategoryUpdateAllowed(const FurnitureGraph& graph, const GraphState& state, const Description& d,
                           const Match& match, double category_floor, const std::vector<Match>& earlier);
// The category half of eq. 5.4 alone (what ApplyMatch holds back for an ambiguous step), in place.
void ApplyCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         double sigma, double category_floor, const std::vector<Match>& earlier);

struct Hypothesis {
  std::int64_t id = 0;                  // G0 = 0, then 1, 2, ... across steps (figure 5.8)
  std::int64_t parent_id = -1;          // the predecessor at the previous step; -1 for G0
  std::optional<Scheme> scheme;         // none for G0
  double score = 0.0;                   // accumulated S over the sequence (kSequential), log-joint in nats (kJoint)
  GraphState state;
  std::vector<Match> matches;           // the sequence of matches, one per description, oldest first
  std::vector<std::int64_t> lineage;    // lineage[t]: id of the ancestor created by description t (last = id)
  std::vector<int> lineage_ranks;       // lineage_ranks[t]: its rank (0 = best) among the n kept at step t
};

// A description whose best interpretations disagreed about the pieces it means: its category update is held back in
// every hypothesis until a later description or an explicit resolution settles it (engine/grounding/ambiguity.h).
struct HeldStep {
  int step = 0;  // 0-based index of the description (matches[step])
  Description description;
};

struct HypothesisSet {
  int step = 0;                   // descriptions grounded so far
  std::int64_t next_id = 1;
  std::vector<Hypothesis> ranked;  // best first
  std::vector<HeldStep> held;      // unsettled ambiguous steps, oldest first
};

// How a hypothesis is scored (issue 17).
//  kSequential - the thesis: S of eq. 5.2 on the state left by the previous descriptions' damped updates (eq. 5.4),
//                summed over the sequence; adaptation by one assessment scheme per sequence (5.3.4).
//  kJoint      - the log of the joint probability of the hypothesis' descriptions, summed step by step as
//                log P(d_t | d_1..d_t-1) with the pieces' categories, the references' orientations and the speaker's
//                frame preference as latent quantities (engine/grounding/joint_model.h). Units: nats.
enum class Model : std::uint8_t { kSequential = 0, kJoint = 1 };
const char* ModelId(Model m);  // "sequential", "joint"

// The joint model's constants (engine/grounding/joint_model.h says how each enters).
struct JointParams {
  double edge_fit_slack = 0.5;         // share of an edge's relation fit that is uniform (borderline angles), [0, 1]
  double line_of_sight_weight = 0.5;   // share of the line-of-sight frame in a relative reading's fit, [0, 1]
  double proximity_scale_m = 0.2;      // P(reference | located) ∝ exp(-gap / scale) over the located piece's edges [m]
  double frame_prior_strength = 5.0;   // pseudo-descriptions of the Beta prior over the speaker's frame preference
  double naming_noise = 0.05;          // P(a speaker names a piece by another category than its own), (0, 1)
  double repeat_weight = 0.0;          // share of its own score a repeated reading adds (joint_model.h), [0, 1]
};

struct GroundingParams {
  Model model = Model::kSequential;
  JointParams joint;
  int n_best = 100;
  double sigma = 3.0;
  // Schemes tried from G0: {S, R, I} = adaptation; {S} = statistics only; {U} = uniform frame prior.
  std::vector<Scheme> schemes = {Scheme::kStatistical, Scheme::kRelative, Scheme::kIntrinsic};
  // Ambiguity (engine/grounding/ambiguity.h). A step is ambiguous when a hypothesis matching the description to
  // another pair of pieces has an accumulated score within ambiguity_margin of the best one; its category update
  // is then held back. 0 = off (the thesis). Units: those of the model's score: S (eq. 5.2) accumulated for
  // kSequential, nats for kJoint.
  double ambiguity_margin = 0.0;
  // A vertex's p(f) moves only towards a category it already holds with p >= category_floor (0 = the thesis).
  double category_floor = 0.0;
};

// The category half of a match's update under `params.model` (ApplyCategoryUpdate for kSequential, the Bayes
// update of joint_model.h for kJoint), with the same poor-match rule; in place.
void ApplyCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         const GroundingParams& params, const std::vector<Match>& earlier);

// The set holding only G0, the graph as seen.
HypothesisSet InitialHypotheses(const FurnitureGraph& graph);

// Grounds one description: every hypothesis x directed edge x interpretation (x scheme for G0), keeps the n best.
HypothesisSet Ground(const FurnitureGraph& graph, const Knowledge& knowledge, const HypothesisSet& current,
                     const Description& d, const GroundingParams& params);

// Speech production (5.3.5): how this listener most likely names the located piece, the reference piece and
// their relation, from the best hypothesis (its p(f), p(r), p(o) and its scheme of frame use).
struct Production {
  int located_category = 0;
  double located_probability = 0.0;
  int reference_category = 0;
  double reference_probability = 0.0;
  Relation relation = Relation::kLeftOf;     // the word to say
  Frame frame = Frame::kRelative;            // the frame it is most likely meant in
  Distribution4 word_probability{};          // P(word) for each relation word
  Scheme scheme = Scheme::kStatistical;
};
// Throws Error(kUnprocessable) when the two vertices share no edge.
Production Produce(const FurnitureGraph& graph, const Knowledge& knowledge, const Hypothesis& best, int located,
                   int reference);

// The word a listener of `best` most likely uses for a located thing whose relation to vertex `reference`, seen
// from the viewpoint, is distributed as `relative` (p(r')): the frame choice of Produce, for objects that are not
// vertices of the graph (where-is answers, SPEC §4.4).
struct WordChoice {
  Relation word = Relation::kLeftOf;
  Frame frame = Frame::kRelative;
  Distribution4 word_probability{};
};
WordChoice PreferredWord(const Knowledge& knowledge, const Hypothesis& best, int category_count, int reference,
                         const Distribution4& relative);

}  // namespace anchordb::engine::grounding
