#include "engine/grounding/readings.h"

#include <algorithm>

namespace anchordb::engine::grounding {

int MostProbableCategory(const GraphState& state, int category_count, int vertex) {
  const double* p = &state.category[static_cast<std::size_t>(vertex) * static_cast<std::size_t>(category_count)];
  return static_cast<int>(std::max_element(p, p + category_count) - p);
}

std::optional<Orientation> KnownFront(const GraphState& state, int vertex) {
  const double* p = &state.orientation[static_cast<std::size_t>(vertex) * kOrientationCount];
  const int front = static_cast<int>(std::max_element(p, p + kOrientationCount) - p);
  if (std::count(p, p + kOrientationCount, p[front]) != 1) return std::nullopt;
  return static_cast<Orientation>(front);
}

bool IsRevised(const Hypothesis& hypothesis) {
  for (std::size_t t = 0; t + 1 < hypothesis.lineage_ranks.size(); ++t) {
    if (hypothesis.lineage_ranks[t] != 0) return true;
  }
  return false;
}

std::vector<Scheme> SchemesToTry(bool adaptation, bool uniform_frame_prior) {
  const Scheme base = uniform_frame_prior ? Scheme::kUniform : Scheme::kStatistical;
  if (!adaptation) return {base};
  return {base, Scheme::kRelative, Scheme::kIntrinsic};
}

std::array<Relation, kRelationCount> WordsByProbability(const Distribution4& word_probability) {
  std::array<Relation, kRelationCount> order = {Relation::kLeftOf, Relation::kRightOf, Relation::kInFrontOf, Relation::kBehind};
  std::stable_sort(order.begin(), order.end(), [&](Relation x, Relation y) {
    return word_probability[static_cast<std::size_t>(x)] > word_probability[static_cast<std::size_t>(y)];
  });
  return order;
}

std::string ProductionSentence(const std::string& located_name, Relation word, const std::string& reference_name) {
  return "the " + located_name + " is " + RelationPhrase(word) + " the " + reference_name;
}

std::string PlacementPhrase(std::optional<Relation> word, const std::string& piece_name) {
  if (!word) return "on the " + piece_name;
  return std::string(RelationPhrase(*word)) + " the " + piece_name;
}

}  // namespace anchordb::engine::grounding
