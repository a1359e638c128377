// The engine's grounding hypotheses <-> storage's stored records (one field each way).
#include "services/furniture/hypotheses_records.h"

#include <utility>

#include "storage/hypotheses_codec.h"

namespace anchordb::services {

namespace g = engine::grounding;

namespace {

storage::HypothesesShape ShapeOf(const g::FurnitureGraph& graph) {
  return {static_cast<int>(graph.vertices.size()), graph.category_count, graph.DirectedEdgeCount(), g::kRelationCount,
          g::kOrientationCount, g::kSchemeCount, g::kInterpretationCount};
}

storage::StoredHypothesis ToStored(const g::Hypothesis& h) {
  storage::StoredHypothesis s;
  s.id = h.id;
  s.parent_id = h.parent_id;
  if (h.scheme) s.scheme = static_cast<int>(*h.scheme);
  s.score = h.score;
  for (const g::Match& m : h.matches) {
    s.matches.push_back({m.directed_edge, m.interpretation, static_cast<int>(m.relative), static_cast<int>(m.scheme), m.score,
                         m.located_category, m.reference_category});
  }
  s.lineage = h.lineage;
  s.lineage_ranks = h.lineage_ranks;
  s.category = h.state.category;
  s.orientation = h.state.orientation;
  s.relation = h.state.relation;
  return s;
}

g::Hypothesis FromStored(storage::StoredHypothesis s) {
  g::Hypothesis h;
  h.id = s.id;
  h.parent_id = s.parent_id;
  if (s.scheme) h.scheme = static_cast<g::Scheme>(*s.scheme);
  h.score = s.score;
  for (const storage::StoredMatch& m : s.matches) {
    g::Match match;
    match.directed_edge = m.directed_edge;
    match.interpretation = m.interpretation;
    match.relative = static_cast<g::Relation>(m.relation);
    match.scheme = static_cast<g::Scheme>(m.scheme);
    match.score = m.score;
    match.located_category = m.located_category;
    match.reference_category = m.reference_category;
    h.matches.push_back(match);
  }
  h.lineage = std::move(s.lineage);
  h.lineage_ranks = std::move(s.lineage_ranks);
  h.state.category = std::move(s.category);
  h.state.orientation = std::move(s.orientation);
  h.state.relation = std::move(s.relation);
  return h;
}

}  // namespace

std::string EncodeHypotheses(const g::FurnitureGraph& graph, const g::HypothesisSet& set) {
  storage::StoredHypothesisSet stored;
  stored.step = set.step;
  stored.next_id = set.next_id;
  for (const g::Hypothesis& h : set.ranked) stored.ranked.push_back(ToStored(h));
  for (const g::HeldStep& held : set.held) {
    stored.held.push_back({held.step, held.description.located, static_cast<int>(held.description.relation),
                           held.description.reference});
  }
  return storage::EncodeHypotheses(ShapeOf(graph), stored);
}

g::HypothesisSet DecodeHypotheses(const g::FurnitureGraph& graph, std::string_view blob) {
  storage::StoredHypothesisSet stored = storage::DecodeHypotheses(ShapeOf(graph), blob);
  g::HypothesisSet set;
  set.step = stored.step;
  set.next_id = stored.next_id;
  for (storage::StoredHypothesis& h : stored.ranked) set.ranked.push_back(FromStored(std::move(h)));
  for (const storage::StoredHeldStep& held : stored.held) {
    set.held.push_back({held.step, {held.located, static_cast<g::Relation>(held.relation), held.reference}});
  }
  return set;
}

}  // namespace anchordb::services
