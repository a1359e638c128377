#pragma once
// The joint model of grounding (issue 17; GroundingParams::model = Model::kJoint). A hypothesis assigns each
// description of the sequence to a directed edge and an interpretation (relative frame, or intrinsic frame with the
// reference's front at o), as in the thesis; it is scored by the log of the joint probability of all its
// descriptions instead of a sum of per-description scores on a damped state. By the chain rule that log is the sum
// over steps of log P(d_t | d_1..d_t-1, assignment), and each step's term is
//
//   log P(named located category | v_loc)      the pieces' categories are latent: p(f) of the state is their
//   + log P(named reference category | v_ref)  posterior, P(named c) = (1 - eps) p(c) + eps / (K - 1) (1 - p(c))
//   + log P(reference | located)               the speaker names a neighbour: ∝ exp(-gap / proximity_scale_m)
//                                              over the located piece's edges
//   + log P(frame | speaker so far)            the speaker's preference for the intrinsic frame is latent with a
//                                              Beta prior of mean P_scheme(intrinsic | nature, o, r') and strength
//                                              frame_prior_strength (in descriptions); its posterior mean after
//                                              n_I intrinsic of n readings of references with a front is
//                                              (strength x mean + n_I) / (strength + n) (Beta-Bernoulli); pieces
//                                              without a front keep the prior and do not count
//   + log p(o | v_ref)                         intrinsic readings: the reference's orientation is latent, p(o) of
//                                              the state its posterior
//   + log L(word | edge, frame, o)             the geometric fit: for the relative frame a mixture of the edge's
//                                              p(r) along the viewing direction and along the line of sight to the
//                                              reference (line_of_sight_weight), for the intrinsic frame p(r' =
//                                              I(word | o)); either is mixed with the uniform by edge_fit_slack.
//
// The update after a match is the posterior of those latent quantities: p(f) of both pieces by Bayes with the
// naming noise (not for a poor match: a described category below category_floor on its piece, unless another
// description of the sequence named the piece so — the rule of ApplyMatch), p(o) of the reference by Bayes with
// L(word | edge, intrinsic, o) for every o after an intrinsic reading. p(r) of the directed edge moves towards r' by
// eq. 5.4 (what a client is shown; the fit itself always uses the geometry). Scores are in nats (<= 0 per step).
//
// A repeat - the same words (categories and relation word) said again and read as the same pieces in the same way
// as an earlier description of the hypothesis - is not independent evidence: it counts once. Its reading scores
// 0 nats (the speaker repeating what it said), updates nothing and does not count again in the frame preference;
// a reading of the repeated words as other pieces, or the same pieces in another frame, is scored as any
// description. Without this a piece that one reading renamed fits every repetition of it for free, and a sequence
// that repeats one description five times counts its naming five times.
#include <array>
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::engine::grounding {

// The terms of one description that do not depend on a hypothesis, per directed edge.
struct JointDescriptionTerms {
  Nature nature = Nature::kNone;  // of the named reference category
  std::array<Relation, kOrientationCount> intrinsic_relative{};  // r' = I(word | intrinsic, o)
  std::vector<double> log_proximity;                             // log P(reference | located)
  std::vector<double> relative_fit;                              // L(word | edge, relative)
  std::vector<std::array<double, kOrientationCount>> intrinsic_fit;  // L(word | edge, intrinsic, o)
};
JointDescriptionTerms JointTerms(const FurnitureGraph& graph, const Knowledge& knowledge, const Description& d,
                                 const JointParams& params);

// Whether two matches read the same words as the same pieces the same way: directed edge, interpretation, r' and
// both named categories equal (r' and the interpretation fix the word). Matches without recorded categories never do.
bool SameReading(const Match& a, const Match& b);
// Whether matches[index] repeats a match at a lower index (SameReading).
bool RepeatsEarlier(const std::vector<Match>& matches, std::size_t index);

// Intrinsic and all readings of references with an intrinsic front among `matches` (the speaker's evidence); a
// repeat (RepeatsEarlier) is not counted again.
struct FrameCounts {
  int intrinsic = 0;
  int total = 0;
};
FrameCounts CountFrames(const Knowledge& knowledge, const std::vector<Match>& matches);

// Posterior mean of the speaker's preference for the intrinsic frame: (strength p0 + n_I) / (strength + n).
double IntrinsicPreference(double prior_mean, const FrameCounts& counts, double strength);

// P(named category | piece) with the naming noise eps: (1 - eps) p(c) + eps / (K - 1) (1 - p(c)).
double NamingProbability(double p_category, int category_count, double naming_noise);

// The 5 interpretations of `d` on every directed edge for hypothesis `parent`: out[e * 5 + i], scores in nats
// (InterpretationScore::rho = P(frame) p(o) L, the relation part). `scheme` gives the frame prior's mean.
void JointScores(const FurnitureGraph& graph, const Knowledge& knowledge, const GroundingParams& params, Scheme scheme,
                 const JointDescriptionTerms& terms, const Description& d, const Hypothesis& parent,
                 std::vector<InterpretationScore>& out);

// The joint model's update of `state` by `match` of `d` (see above); `categories` = false holds the category part
// back (an ambiguous step). A match that repeats one of `earlier` (SameReading) changes nothing.
GraphState JointApplyMatch(const FurnitureGraph& graph, const GraphState& state, const Knowledge& knowledge,
                           const Description& d, const Match& match, const GroundingParams& params, bool categories,
                           const std::vector<Match>& earlier);

// The category part alone, in place: Bayes with the naming noise on both pieces, nothing on a poor match.
void JointCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         double naming_noise, double category_floor, const std::vector<Match>& earlier);

}  // namespace anchordb::engine::grounding
