#pragma once
// Ambiguity as an answer of grounding (issue 17). The n best hypotheses of thesis 5.3.3 already hold the competing
// readings of a description; this file reads them:
//  - the alternatives of step t: the distinct (located, reference) vertex pairs that the hypotheses match
//    description t to, each with the best accumulated score among the hypotheses that do, best first, down to
//    `margin` below the best (units of S, eq. 5.2, accumulated over the sequence);
//  - a step is ambiguous when more than one pair is within the margin. Grounding then holds the category half of
//    eq. 5.4 back in every hypothesis (relations and orientations still move: they are what lets later
//    descriptions tell the readings apart) and records the step as held;
//  - a held step settles when a later description leaves a single pair within the margin, or when a client names
//    the pair (KeepPair): every live hypothesis then applies the held category update of its own match.
// A poor match - a described category below `category_floor` on the piece it is matched to - does not move that
// piece's p(f) (ApplyMatch) unless another description of the same sequence named the piece so too.
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::engine::grounding {

struct Alternative {
  int located = -1;     // vertex
  int reference = -1;   // vertex
  int rank = 0;         // rank (0 = best) of the best hypothesis matching the description to this pair
  double total = 0.0;   // its accumulated score
  Match match;          // its match of the description
};

// The alternatives of description `step` (0-based) in `set`, best first, at most `max_count` (>= 1). The first is
// always the best hypothesis' pair. Empty when no hypothesis has matched `step` yet.
std::vector<Alternative> AlternativesAt(const FurnitureGraph& graph, const HypothesisSet& set, int step, double margin,
                                        int max_count);

// Whether `match` of `d` is poor: a described category has p < category_floor on its piece in `state` (the state
// after the match: a poor match leaves that p as it was, or raises it once confirmed).
bool IsPoorMatch(const FurnitureGraph& graph, const GraphState& state, const Description& d, const Match& match,
                 double category_floor);

// Applies the held category update of held step `held_index` in every hypothesis and removes it from set.held.
void SettleHeld(const FurnitureGraph& graph, HypothesisSet& set, std::size_t held_index, double sigma, double category_floor);
// The same under params.model (the joint model's category update for kJoint).
void SettleHeld(const FurnitureGraph& graph, HypothesisSet& set, std::size_t held_index, const GroundingParams& params);

// Settles every held step that now has a single alternative within params.ambiguity_margin. Returns the steps
// settled (0-based), oldest first.
std::vector<int> SettleClearSteps(const FurnitureGraph& graph, HypothesisSet& set, const GroundingParams& params);

// An explicit resolution: keeps only the hypotheses that match held step `step` to (located, reference), then
// settles it. Error(kConflict) when `step` is not held; Error(kUnprocessable) when no live hypothesis matches the
// description to that pair, or its reading fits poorly (those pieces are not believed to be what it names). `set` is
// unchanged on error.
void KeepPair(const FurnitureGraph& graph, HypothesisSet& set, int step, int located, int reference, double sigma,
              double category_floor);
// The same under params.model.
void KeepPair(const FurnitureGraph& graph, HypothesisSet& set, int step, int located, int reference,
              const GroundingParams& params);

}  // namespace anchordb::engine::grounding
