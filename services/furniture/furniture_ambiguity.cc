// The competing readings of a description and the question the robot asks back (issue 17), in the words of speech
// production (thesis 5.3.5): each reading's piece is told apart by its most likely description relative to a
// neighbouring piece that is not itself in question.
#include <algorithm>
#include <set>

#include "services/furniture/furniture_service_internal.h"
#include "engine/grounding/ambiguity.h"
#include "engine/grounding/readings.h"

namespace anchordb::services::furniture_detail {

namespace {

constexpr int kMaxAlternatives = 3;

// "the table to the left of the sofa": piece `v` named `name`, placed relative to the neighbour the listener most
// likely uses, avoiding the pieces in question; just "the table" when it has no such neighbour.
std::string Phrase(const FurnitureService::Graph& gr, int v, const std::string& name, const std::set<int>& avoid) {
  const g::FurnitureGraph& graph = gr.graph;
  const g::Hypothesis& best = gr.set.ranked.front();
  double best_p = -1.0;
  std::string out = "the " + name;
  for (std::size_t e = 0; e < graph.edges.size(); ++e) {
    const int other = graph.edges[e].a == v ? graph.edges[e].b : graph.edges[e].b == v ? graph.edges[e].a : -1;
    if (other < 0 || avoid.count(other)) continue;
    const g::Production p = g::Produce(graph, gr.knowledge, best, v, other);
    const double score = p.word_probability[static_cast<std::size_t>(p.relation)] * p.reference_probability;
    if (score > best_p) {
      best_p = score;
      out = "the " + name + " " + g::RelationPhrase(p.relation) + " the " + gr.knowledge.categories[p.reference_category].name;
    }
  }
  return out;
}

}  // namespace

AmbiguityView AmbiguityOf(const FurnitureService::Graph& gr, int step, const g::Description& d, bool ambiguous, bool poor) {
  const g::FurnitureGraph& graph = gr.graph;
  const auto& cats = gr.knowledge.categories;
  AmbiguityView out;
  out.seq = step + 1;
  out.ambiguous = ambiguous;
  out.poor = poor;
  const double margin = gr.params.ambiguity_margin;
  const auto alternatives = g::AlternativesAt(graph, gr.set, step, margin, ambiguous ? kMaxAlternatives : 1);
  if (alternatives.empty()) return out;
  // Tell the readings apart by the piece in which they differ (the located one when both differ).
  const bool located_differs = std::any_of(alternatives.begin(), alternatives.end(),
                                           [&](const g::Alternative& a) { return a.located != alternatives.front().located; });
  std::set<int> in_question;
  for (const g::Alternative& a : alternatives) in_question.insert(located_differs ? a.located : a.reference);
  std::vector<std::string> phrases;
  for (const g::Alternative& a : alternatives) {
    AlternativeView& view = out.alternatives.emplace_back();
    view.match = MatchOf(graph, a.match);
    view.total = a.total;
    if (!ambiguous) {
      // A poor fit: say what the robot sees there, in its own labels.
      const g::Production p = g::Produce(graph, gr.knowledge, gr.set.ranked.front(), a.located, a.reference);
      view.phrase = "the " + cats[p.located_category].name + " " + g::RelationPhrase(p.relation) + " the " +
                    cats[p.reference_category].name;
    } else if (located_differs) {
      view.phrase = Phrase(gr, a.located, cats[d.located].name, in_question);
    } else {
      view.phrase = Phrase(gr, a.reference, cats[d.reference].name, in_question);
    }
    phrases.push_back(view.phrase);
  }
  if (!ambiguous) {
    out.question = "I do not see a " + cats[d.located].name + " " + g::RelationPhrase(d.relation) + " a " +
                   cats[d.reference].name + "; do you mean " + phrases.front() + "?";
    return out;
  }
  out.question = "do you mean ";
  for (std::size_t i = 0; i < phrases.size(); ++i) {
    if (i > 0) out.question += i + 1 == phrases.size() ? " or " : ", ";
    out.question += phrases[i];
  }
  out.question += "?";
  return out;
}

std::vector<AmbiguityView> PendingOf(const FurnitureService::Graph& gr) {
  std::vector<AmbiguityView> out;
  for (const g::HeldStep& h : gr.set.held) out.push_back(AmbiguityOf(gr, h.step, h.description, true, false));
  return out;
}

}  // namespace anchordb::services::furniture_detail
