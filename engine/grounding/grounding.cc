#include "engine/grounding/grounding.h"

#include <algorithm>
#include <cmath>

#include "engine/grounding/ambiguity.h"
#include "engine/grounding/joint_model.h"
#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace {

// I(word | intrinsic, o) for every nature, orientation and word, computed once.
struct IntrinsicTable {
  Relation to_relative[kNatureCount][kOrientationCount][kRelationCount];
  IntrinsicTable() {
    for (int n = 0; n < kNatureCount; ++n) {
      for (int o = 0; o < kOrientationCount; ++o) {
        for (int w = 0; w < kRelationCount; ++w) {
          to_relative[n][o][w] = IntrinsicToRelative(static_cast<Relation>(w), static_cast<Nature>(n), static_cast<Orientation>(o));
        }
      }
    }
  }
};

const IntrinsicTable& Intrinsic() {
  static const IntrinsicTable kTable;
  return kTable;
}

std::size_t Idx(int v) { return static_cast<std::size_t>(v); }

void CheckDescription(const Knowledge& knowledge, const Description& d) {
  const int k = knowledge.categories.size();
  if (d.located < 0 || d.located >= k || d.reference < 0 || d.reference >= k) {
    throw Error(ErrorCode::kInvalidArgument, "description names a category outside the table");
  }
  if (static_cast<int>(d.relation) >= kRelationCount) {
    throw Error(ErrorCode::kInvalidArgument, "description has a relation outside the vocabulary", "relation");
  }
}

struct Candidate {
  double total = 0.0;
  double step = 0.0;
  std::uint64_t order = 0;  // generation order: (parent rank, scheme, edge, interpretation)
  std::uint32_t parent = 0;
  std::uint16_t directed = 0;
  std::uint8_t interpretation = 0;
  Scheme scheme = Scheme::kStatistical;
  Relation relative = Relation::kLeftOf;
};

}  // namespace

std::array<InterpretationScore, kInterpretationCount> ScoreInterpretations(const FurnitureGraph& graph,
                                                                           const GraphState& state,
                                                                           const Knowledge& knowledge, Scheme s,
                                                                           const Description& d, int directed) {
  const int k = graph.category_count;
  const int a = graph.Located(directed), b = graph.Reference(directed);
  const double categories = state.category[Idx(a * k + d.located)] + state.category[Idx(b * k + d.reference)];
  const Nature nature = knowledge.categories[d.reference].nature;
  const double* p_r = &state.relation[Idx(directed * kRelationCount)];
  const double* p_o = &state.orientation[Idx(b * kOrientationCount)];
  const FramePrior& prior = knowledge.prior;
  std::array<InterpretationScore, kInterpretationCount> out{};
  double best_relative = 0.0;
  for (int o = 0; o < kOrientationCount; ++o) {
    best_relative = std::max(best_relative, p_o[o] * prior.Probability(s, Frame::kRelative, nature, static_cast<Orientation>(o), d.relation));
  }
  out[0].relative = d.relation;
  out[0].rho = p_r[static_cast<int>(d.relation)] * best_relative;
  out[0].score = (categories + out[0].rho) / 3.0;
  const auto& to_relative = Intrinsic().to_relative[static_cast<int>(nature)];
  for (int o = 0; o < kOrientationCount; ++o) {
    const Relation r = to_relative[o][static_cast<int>(d.relation)];
    InterpretationScore& x = out[Idx(o + 1)];
    x.relative = r;
    x.rho = p_r[static_cast<int>(r)] * prior.Probability(s, Frame::kIntrinsic, nature, static_cast<Orientation>(o), r) * p_o[o];
    x.score = (categories + x.rho) / 3.0;
  }
  return out;
}

void DampedUpdate(double* p, const double* target, int size, double sigma) {
  double sum = 0.0;
  for (int i = 0; i < size; ++i) sum += p[i] += (target[i] - p[i]) / sigma;
  if (sum > 0.0) {
    for (int i = 0; i < size; ++i) p[i] /= sum;
  }
}

Distribution4 OrientationTarget(const FurnitureGraph& graph, int directed, Relation word, Nature nature) {
  const Distribution4& visual = graph.Visual(directed);
  Distribution4 t{};
  double sum = 0.0;
  for (int o = 0; o < kOrientationCount; ++o) {
    sum += t[Idx(o)] = visual[Idx(static_cast<int>(Intrinsic().to_relative[static_cast<int>(nature)][o][static_cast<int>(word)]))];
  }
  if (sum > 0.0) {
    for (double& v : t) v /= sum;
  }
  return t;
}

const char* ModelId(Model m) { return m == Model::kJoint ? "joint" : "sequential"; }

bool CategoryUpdateAllowed(const FurnitureGraph& graph, const GraphState& state, const Description& d,
                           const Match& match, double category_floor, const std::vector<Match>& earlier) {
  const int k = graph.category_count;
  const int vertices[2] = {graph.Located(match.directed_edge), graph.Reference(match.directed_edge)};
  const int described[2] = {d.located, d.reference};
  const auto named_before = [&](int vertex, int category) {
    return std::any_of(earlier.begin(), earlier.end(), [&](const Match& m) {
      return (graph.Located(m.directed_edge) == vertex && m.located_category == category) ||
             (graph.Reference(m.directed_edge) == vertex && m.reference_category == category);
    });
  };
  // A poor match (a described category below the floor on its piece, not said of it before in this sequence) moves
  // no category at all: the description does not fit, so neither of its pieces is confirmed by it.
  for (int i = 0; i < 2; ++i) {
    if (state.category[Idx(vertices[i] * k + described[i])] < category_floor && !named_before(vertices[i], described[i])) return false;
  }
  return true;
}

void ApplyCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         double sigma, double category_floor, const std::vector<Match>& earlier) {
  if (!CategoryUpdateAllowed(graph, state, d, match, category_floor, earlier)) return;
  const int k = graph.category_count;
  const int vertices[2] = {graph.Located(match.directed_edge), graph.Reference(match.directed_edge)};
  const int described[2] = {d.located, d.reference};
  std::vector<double> target(Idx(k), 0.0);
  for (int i = 0; i < 2; ++i) {
    double* row = &state.category[Idx(vertices[i] * k)];
    target[Idx(described[i])] = 1.0;
    DampedUpdate(row, target.data(), k, sigma);
    target[Idx(described[i])] = 0.0;
  }
}

void ApplyCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         const GroundingParams& params, const std::vector<Match>& earlier) {
  if (params.model == Model::kJoint) {
    JointCategoryUpdate(graph, state, d, match, params.joint.naming_noise, params.category_floor, earlier);
  } else {
    ApplyCategoryUpdate(graph, state, d, match, params.sigma, params.category_floor, earlier);
  }
}

GraphState ApplyMatch(const FurnitureGraph& graph, const GraphState& state, const Knowledge& knowledge,
                      const Description& d, const Match& match, double sigma, double category_floor, bool categories,
                      const std::vector<Match>& earlier) {
  GraphState out = state;
  const int b = graph.Reference(match.directed_edge);
  if (categories) ApplyCategoryUpdate(graph, out, d, match, sigma, category_floor, earlier);
  Distribution4 relation{};
  relation[Idx(static_cast<int>(match.relative))] = 1.0;
  DampedUpdate(&out.relation[Idx(match.directed_edge * kRelationCount)], relation.data(), kRelationCount, sigma);
  if (FrameOf(match.interpretation) == Frame::kIntrinsic) {
    const Distribution4 t = OrientationTarget(graph, match.directed_edge, d.relation, knowledge.categories[d.reference].nature);
    DampedUpdate(&out.orientation[Idx(b * kOrientationCount)], t.data(), kOrientationCount, sigma);
  }
  return out;
}

HypothesisSet InitialHypotheses(const FurnitureGraph& graph) {
  HypothesisSet set;
  Hypothesis g0;
  g0.id = 0;
  g0.state = graph.initial;
  set.ranked.push_back(std::move(g0));
  set.next_id = 1;
  return set;
}

HypothesisSet Ground(const FurnitureGraph& graph, const Knowledge& knowledge, const HypothesisSet& current,
                     const Description& d, const GroundingParams& params) {
  CheckDescription(knowledge, d);
  if (graph.category_count != knowledge.categories.size()) {
    throw Error(ErrorCode::kInternal, "graph and knowledge disagree on the number of categories");
  }
  if (graph.edges.empty()) throw Error(ErrorCode::kUnprocessable, "the furniture graph has no edges");
  if (current.ranked.empty()) throw Error(ErrorCode::kInternal, "no live hypothesis");
  if (params.n_best < 1 || !(params.sigma >= 1.0) || params.schemes.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "grounding needs n_best >= 1, sigma >= 1 and at least one scheme");
  }
  const int directed_count = graph.DirectedEdgeCount();
  std::vector<Candidate> candidates;
  candidates.reserve(current.ranked.size() * Idx(directed_count) * kInterpretationCount *
                     (current.step == 0 ? params.schemes.size() : 1));
  std::uint64_t order = 0;
  const bool joint = params.model == Model::kJoint;
  JointDescriptionTerms terms;
  std::vector<InterpretationScore> joint_scores;
  if (joint) terms = JointTerms(graph, knowledge, d, params.joint);
  for (std::size_t p = 0; p < current.ranked.size(); ++p) {
    const Hypothesis& parent = current.ranked[p];
    for (const Scheme s : params.schemes) {
      if (parent.scheme && *parent.scheme != s) continue;
      // The joint model has one scheme: the first gives its frame prior's mean; the speaker's posterior adapts.
      if (joint && s != params.schemes.front()) continue;
      if (joint) JointScores(graph, knowledge, params, s, terms, d, parent, joint_scores);
      for (int e = 0; e < directed_count; ++e) {
        std::array<InterpretationScore, kInterpretationCount> scores;
        if (joint) {
          std::copy_n(joint_scores.begin() + static_cast<std::ptrdiff_t>(e * kInterpretationCount), kInterpretationCount, scores.begin());
        } else {
          scores = ScoreInterpretations(graph, parent.state, knowledge, s, d, e);
        }
        for (int i = 0; i < kInterpretationCount; ++i) {
          Candidate c;
          c.step = scores[Idx(i)].score;
          c.total = parent.score + c.step;
          c.order = order++;
          c.parent = static_cast<std::uint32_t>(p);
          c.directed = static_cast<std::uint16_t>(e);
          c.interpretation = static_cast<std::uint8_t>(i);
          c.scheme = s;
          c.relative = scores[Idx(i)].relative;
          candidates.push_back(c);
        }
      }
    }
  }
  if (candidates.empty()) {
    throw Error(ErrorCode::kInternal, "no hypothesis can continue: its scheme is not among the configured schemes");
  }
  const std::size_t keep = std::min(candidates.size(), Idx(params.n_best));
  std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(keep), candidates.end(),
                    [](const Candidate& x, const Candidate& y) {
                      if (x.total != y.total) return x.total > y.total;
                      return x.order < y.order;
                    });
  HypothesisSet next;
  next.step = current.step + 1;
  next.next_id = current.next_id;
  next.held = current.held;
  next.ranked.reserve(keep);
  std::vector<std::uint32_t> parents;
  parents.reserve(keep);
  for (std::size_t rank = 0; rank < keep; ++rank) {
    const Candidate& c = candidates[rank];
    const Hypothesis& parent = current.ranked[c.parent];
    Hypothesis h;
    h.id = next.next_id++;
    h.parent_id = parent.id;
    h.scheme = c.scheme;
    h.score = c.total;
    Match m;
    m.directed_edge = c.directed;
    m.interpretation = c.interpretation;
    m.relative = c.relative;
    m.scheme = c.scheme;
    m.score = c.step;
    m.located_category = d.located;
    m.reference_category = d.reference;
    h.matches = parent.matches;
    h.matches.push_back(m);
    h.lineage = parent.lineage;
    h.lineage.push_back(h.id);
    h.lineage_ranks = parent.lineage_ranks;
    h.lineage_ranks.push_back(static_cast<int>(rank));
    parents.push_back(c.parent);
    next.ranked.push_back(std::move(h));
  }
  // The matches decide whether this step is ambiguous before any state is updated (its categories are held back).
  // A best reading that fits poorly is answered as such (its categories do not move anyway), not held as ambiguous.
  const bool ambiguous = params.ambiguity_margin > 0.0 &&
                         AlternativesAt(graph, next, current.step, params.ambiguity_margin, 2).size() > 1 &&
                         !(params.category_floor > 0.0 && IsPoorMatch(graph, current.ranked[parents[0]].state, d,
                                                                        next.ranked.front().matches.back(), params.category_floor));
  if (ambiguous) next.held.push_back({current.step, d});
  for (std::size_t rank = 0; rank < keep; ++rank) {
    Hypothesis& h = next.ranked[rank];
    const Hypothesis& parent = current.ranked[parents[rank]];
    h.state = joint ? JointApplyMatch(graph, parent.state, knowledge, d, h.matches.back(), params, !ambiguous, parent.matches)
                    : ApplyMatch(graph, parent.state, knowledge, d, h.matches.back(), params.sigma, params.category_floor,
                                 !ambiguous, parent.matches);
  }
  if (params.ambiguity_margin > 0.0) SettleClearSteps(graph, next, params);
  return next;
}

Production Produce(const FurnitureGraph& graph, const Knowledge& knowledge, const Hypothesis& best, int located,
                   int reference) {
  const int directed = graph.FindDirected(located, reference);
  if (directed < 0) {
    throw Error(ErrorCode::kUnprocessable, "'" + graph.vertices[Idx(located)].id + "' and '" + graph.vertices[Idx(reference)].id +
                                               "' share no edge in the furniture graph (they are too far apart)");
  }
  const int k = graph.category_count;
  const GraphState& s = best.state;
  Production out;
  out.scheme = best.scheme.value_or(Scheme::kStatistical);
  const auto argmax = [&](int v, int& category, double& probability) {
    const double* row = &s.category[Idx(v * k)];
    category = static_cast<int>(std::max_element(row, row + k) - row);
    probability = row[category];
  };
  argmax(located, out.located_category, out.located_probability);
  argmax(reference, out.reference_category, out.reference_probability);
  Distribution4 relative{};
  for (int r = 0; r < kRelationCount; ++r) relative[Idx(r)] = s.relation[Idx(directed * kRelationCount + r)];
  const WordChoice choice = PreferredWord(knowledge, best, k, reference, relative);
  out.word_probability = choice.word_probability;
  out.relation = choice.word;
  out.frame = choice.frame;
  return out;
}

WordChoice PreferredWord(const Knowledge& knowledge, const Hypothesis& best, int category_count, int reference,
                         const Distribution4& relative) {
  const GraphState& s = best.state;
  const Scheme scheme = best.scheme.value_or(Scheme::kStatistical);
  const double* row = &s.category[Idx(reference * category_count)];
  const int category = static_cast<int>(std::max_element(row, row + category_count) - row);
  const Nature nature = knowledge.categories[category].nature;
  // P(word, frame) = sum over the relation r' seen and the orientation o believed of
  //   P(r') P(o | v_ref) P(frame | nature, o, r'), with the word the frame gives for r'.
  double by_frame[kRelationCount][2] = {};
  for (int r = 0; r < kRelationCount; ++r) {
    for (int o = 0; o < kOrientationCount; ++o) {
      const double w = relative[Idx(r)] * s.orientation[Idx(reference * kOrientationCount + o)];
      const auto rel = static_cast<Relation>(r);
      const auto orient = static_cast<Orientation>(o);
      by_frame[r][0] += w * knowledge.prior.Probability(scheme, Frame::kRelative, nature, orient, rel);
      const int word = static_cast<int>(RelativeToIntrinsic(rel, nature, orient));
      by_frame[word][1] += w * knowledge.prior.Probability(scheme, Frame::kIntrinsic, nature, orient, rel);
    }
  }
  WordChoice out;
  int best_word = 0;
  for (int r = 0; r < kRelationCount; ++r) {
    out.word_probability[Idx(r)] = by_frame[r][0] + by_frame[r][1];
    if (out.word_probability[Idx(r)] > out.word_probability[Idx(best_word)]) best_word = r;
  }
  out.word = static_cast<Relation>(best_word);
  out.frame = by_frame[best_word][1] > by_frame[best_word][0] ? Frame::kIntrinsic : Frame::kRelative;
  return out;
}

}  // namespace anchordb::engine::grounding
