#pragma once
// What a hypothesis of a furniture graph says, in the terms a client is told (thesis 5.3): the label of a vertex, its
// front when the belief singles one out, whether the best sequence was revised, the assessment schemes a graph tries,
// the order of alternative words, and the sentences the robot says. Pure functions of the engine's types.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::engine::grounding {

// The label of vertex `vertex` in `state`: the category of largest p(f) (the first of equal maxima).
int MostProbableCategory(const GraphState& state, int category_count, int vertex);

// The front of vertex `vertex`: the orientation of largest p(o) when no other orientation is as probable; nullopt
// while the belief does not single one out (p(o) is uniform until an intrinsic description is grounded).
std::optional<Orientation> KnownFront(const GraphState& state, int vertex);

// A revision (figures 5.9-5.10): the best sequence no longer runs through the best hypothesis of an earlier step,
// i.e. an ancestor before the last step was not ranked first when it was kept.
bool IsRevised(const Hypothesis& hypothesis);

// The schemes a graph expands G0 under: the statistics (or the uniform prior) alone, and with adaptation also the
// relative- and intrinsic-preferring schemes (5.3.4).
std::vector<Scheme> SchemesToTry(bool adaptation, bool uniform_frame_prior);

// The four relation words by falling probability; equal probabilities keep the order of Relation.
std::array<Relation, kRelationCount> WordsByProbability(const Distribution4& word_probability);

// "the shelf is to the right of the sofa" (speech production, 5.3.5).
std::string ProductionSentence(const std::string& located_name, Relation word, const std::string& reference_name);

// Where a thing is relative to a named piece: "on the table" (`word` nullopt) or "to the left of the sofa".
std::string PlacementPhrase(std::optional<Relation> word, const std::string& piece_name);

}  // namespace anchordb::engine::grounding
