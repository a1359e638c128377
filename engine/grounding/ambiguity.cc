#include "engine/grounding/ambiguity.h"

#include <algorithm>

#include "engine/grounding/joint_model.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {

std::vector<Alternative> AlternativesAt(const FurnitureGraph& graph, const HypothesisSet& set, int step, double margin,
                                        int max_count) {
  std::vector<Alternative> out;
  if (set.ranked.empty() || step < 0) return out;
  const double best = set.ranked.front().score;
  for (std::size_t rank = 0; rank < set.ranked.size() && static_cast<int>(out.size()) < max_count; ++rank) {
    const Hypothesis& h = set.ranked[rank];
    if (static_cast<std::size_t>(step) >= h.matches.size()) return out;
    if (!out.empty() && h.score < best - margin) break;  // ranked: nothing further is within the margin
    const Match& m = h.matches[static_cast<std::size_t>(step)];
    const int located = graph.Located(m.directed_edge), reference = graph.Reference(m.directed_edge);
    const bool seen = std::any_of(out.begin(), out.end(), [&](const Alternative& a) {
      return a.located == located && a.reference == reference;
    });
    if (!seen) out.push_back({located, reference, static_cast<int>(rank), h.score, m});
  }
  return out;
}

bool IsPoorMatch(const FurnitureGraph& graph, const GraphState& state, const Description& d, const Match& match,
                 double category_floor) {
  const std::size_t k = static_cast<std::size_t>(graph.category_count);
  const auto p = [&](int vertex, int category) {
    return state.category[static_cast<std::size_t>(vertex) * k + static_cast<std::size_t>(category)];
  };
  return p(graph.Located(match.directed_edge), d.located) < category_floor ||
         p(graph.Reference(match.directed_edge), d.reference) < category_floor;
}

namespace {

GroundingParams SequentialParams(double sigma, double category_floor) {
  GroundingParams p;
  p.sigma = sigma;
  p.category_floor = category_floor;
  return p;
}

}  // namespace

void SettleHeld(const FurnitureGraph& graph, HypothesisSet& set, std::size_t held_index, double sigma, double category_floor) {
  SettleHeld(graph, set, held_index, SequentialParams(sigma, category_floor));
}

void SettleHeld(const FurnitureGraph& graph, HypothesisSet& set, std::size_t held_index, const GroundingParams& params) {
  const HeldStep held = set.held.at(held_index);
  for (Hypothesis& h : set.ranked) {
    if (static_cast<std::size_t>(held.step) >= h.matches.size()) continue;
    // The joint model counts a repeated reading once: its first occurrence carries the update (joint_model.h).
    if (params.model == Model::kJoint && RepeatsEarlier(h.matches, static_cast<std::size_t>(held.step))) continue;
    // Confirmation by any other description of the sequence counts, earlier or later than the held one; under the
    // joint model not the held description's own later repeats (the same reading told again confirms nothing).
    const Match& settled = h.matches[static_cast<std::size_t>(held.step)];
    std::vector<Match> others;
    for (std::size_t i = 0; i < h.matches.size(); ++i) {
      if (i == static_cast<std::size_t>(held.step)) continue;
      if (params.model == Model::kJoint && SameReading(h.matches[i], settled)) continue;
      others.push_back(h.matches[i]);
    }
    ApplyCategoryUpdate(graph, h.state, held.description, h.matches[static_cast<std::size_t>(held.step)], params, others);
  }
  set.held.erase(set.held.begin() + static_cast<std::ptrdiff_t>(held_index));
}

std::vector<int> SettleClearSteps(const FurnitureGraph& graph, HypothesisSet& set, const GroundingParams& params) {
  std::vector<int> settled;
  for (std::size_t i = 0; i < set.held.size();) {
    const int step = set.held[i].step;
    if (AlternativesAt(graph, set, step, params.ambiguity_margin, 2).size() == 1) {
      SettleHeld(graph, set, i, params);
      settled.push_back(step);
    } else {
      ++i;
    }
  }
  return settled;
}

void KeepPair(const FurnitureGraph& graph, HypothesisSet& set, int step, int located, int reference, double sigma,
              double category_floor) {
  KeepPair(graph, set, step, located, reference, SequentialParams(sigma, category_floor));
}

void KeepPair(const FurnitureGraph& graph, HypothesisSet& set, int step, int located, int reference,
              const GroundingParams& params) {
  const double category_floor = params.category_floor;
  const auto held = std::find_if(set.held.begin(), set.held.end(), [&](const HeldStep& h) { return h.step == step; });
  if (held == set.held.end()) {
    throw Error(ErrorCode::kConflict, "description " + std::to_string(step + 1) + " is not awaiting a resolution", "seq");
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < set.ranked.size(); ++i) {
    const Hypothesis& h = set.ranked[i];
    if (static_cast<std::size_t>(step) >= h.matches.size()) continue;
    const int e = h.matches[static_cast<std::size_t>(step)].directed_edge;
    if (graph.Located(e) == located && graph.Reference(e) == reference) kept.push_back(i);
  }
  if (kept.empty()) {
    throw Error(ErrorCode::kUnprocessable, "no live hypothesis matches description " + std::to_string(step + 1) +
                                               " to that pair of pieces", "located");
  }
  const Hypothesis& first = set.ranked[kept.front()];
  if (IsPoorMatch(graph, first.state, held->description, first.matches[static_cast<std::size_t>(step)], category_floor)) {
    throw Error(ErrorCode::kUnprocessable, "those pieces are not believed to be what description " + std::to_string(step + 1) +
                                               " names", "located");
  }
  std::vector<Hypothesis> ranked;
  for (std::size_t i : kept) ranked.push_back(std::move(set.ranked[i]));
  set.ranked = std::move(ranked);
  SettleHeld(graph, set, static_cast<std::size_t>(held - set.held.begin()), params);
}

}  // namespace anchordb::engine::grounding
