#include "engine/grounding/joint_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace anchordb::engine::grounding {
namespace {

std::size_t JointIdx(int v) { return static_cast<std::size_t>(v); }

double SafeLog(double p) { return std::log(std::max(p, std::numeric_limits<double>::min())); }

double Slacked(double p, double slack) { return (1.0 - slack) * p + slack / kRelationCount; }

}  // namespace

JointDescriptionTerms JointTerms(const FurnitureGraph& graph, const Knowledge& knowledge, const Description& d,
                                 const JointParams& params) {
  JointDescriptionTerms t;
  t.nature = knowledge.categories[d.reference].nature;
  for (int o = 0; o < kOrientationCount; ++o) {
    t.intrinsic_relative[JointIdx(o)] = IntrinsicToRelative(d.relation, t.nature, static_cast<Orientation>(o));
  }
  const int directed_count = graph.DirectedEdgeCount();
  t.log_proximity.assign(JointIdx(directed_count), 0.0);
  t.relative_fit.assign(JointIdx(directed_count), 0.0);
  t.intrinsic_fit.assign(JointIdx(directed_count), {});
  // P(reference | located) over the located piece's edges, by the softmax of -gap / scale.
  const double scale = std::max(params.proximity_scale_m, 1e-6);
  std::vector<double> nearest(graph.vertices.size(), std::numeric_limits<double>::infinity());
  for (const Edge& e : graph.edges) {
    nearest[JointIdx(e.a)] = std::min(nearest[JointIdx(e.a)], e.gap_m);
    nearest[JointIdx(e.b)] = std::min(nearest[JointIdx(e.b)], e.gap_m);
  }
  std::vector<double> normaliser(graph.vertices.size(), 0.0);
  for (const Edge& e : graph.edges) {
    normaliser[JointIdx(e.a)] += std::exp(-(e.gap_m - nearest[JointIdx(e.a)]) / scale);
    normaliser[JointIdx(e.b)] += std::exp(-(e.gap_m - nearest[JointIdx(e.b)]) / scale);
  }
  const double w = params.line_of_sight_weight;
  for (int e = 0; e < directed_count; ++e) {
    const Edge& edge = graph.edges[JointIdx(e / 2)];
    const int a = graph.Located(e);
    t.log_proximity[JointIdx(e)] = -(edge.gap_m - nearest[JointIdx(a)]) / scale - std::log(normaliser[JointIdx(a)]);
    const Distribution4& visual = graph.Visual(e);
    const Distribution4& sight = edge.line_of_sight[JointIdx(e % 2)];
    const std::size_t r = JointIdx(static_cast<int>(d.relation));
    t.relative_fit[JointIdx(e)] = Slacked((1.0 - w) * visual[r] + w * sight[r], params.edge_fit_slack);
    for (int o = 0; o < kOrientationCount; ++o) {
      t.intrinsic_fit[JointIdx(e)][JointIdx(o)] =
          Slacked(visual[JointIdx(static_cast<int>(t.intrinsic_relative[JointIdx(o)]))], params.edge_fit_slack);
    }
  }
  return t;
}

bool SameReading(const Match& a, const Match& b) {
  return a.located_category >= 0 && a.reference_category >= 0 && a.directed_edge >= 0 &&
         a.directed_edge == b.directed_edge && a.interpretation == b.interpretation && a.relative == b.relative &&
         a.located_category == b.located_category && a.reference_category == b.reference_category;
}

bool RepeatsEarlier(const std::vector<Match>& matches, std::size_t index) {
  if (index >= matches.size()) return false;
  const auto end = matches.begin() + static_cast<std::ptrdiff_t>(index);
  return std::any_of(matches.begin(), end, [&](const Match& m) { return SameReading(m, matches[index]); });
}

FrameCounts CountFrames(const Knowledge& knowledge, const std::vector<Match>& matches) {
  FrameCounts c;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const Match& m = matches[i];
    if (m.reference_category < 0 || knowledge.categories[m.reference_category].nature == Nature::kNone) continue;
    if (RepeatsEarlier(matches, i)) continue;
    ++c.total;
    c.intrinsic += FrameOf(m.interpretation) == Frame::kIntrinsic;
  }
  return c;
}

double IntrinsicPreference(double prior_mean, const FrameCounts& counts, double strength) {
  return (strength * prior_mean + counts.intrinsic) / (strength + counts.total);
}

double NamingProbability(double p_category, int category_count, double naming_noise) {
  const double other = category_count > 1 ? naming_noise / (category_count - 1) : 0.0;
  return (1.0 - naming_noise) * p_category + other * (1.0 - p_category);
}

void JointScores(const FurnitureGraph& graph, const Knowledge& knowledge, const GroundingParams& params, Scheme scheme,
                 const JointDescriptionTerms& terms, const Description& d, const Hypothesis& parent,
                 std::vector<InterpretationScore>& out) {
  const int k = graph.category_count;
  const std::size_t n = graph.vertices.size();
  const GraphState& s = parent.state;
  const JointParams& jp = params.joint;
  // Per vertex: the naming terms and the frame x orientation terms of a reading with it as reference.
  std::vector<double> log_located(n), log_reference(n), log_relative_frame(n);
  std::vector<std::array<double, kOrientationCount>> log_intrinsic(n);
  std::vector<std::array<double, kOrientationCount>> p_intrinsic_frame(n);
  const FrameCounts counts = CountFrames(knowledge, parent.matches);
  const bool fronted = terms.nature != Nature::kNone;
  for (std::size_t v = 0; v < n; ++v) {
    log_located[v] = SafeLog(NamingProbability(s.category[v * JointIdx(k) + JointIdx(d.located)], k, jp.naming_noise));
    log_reference[v] = SafeLog(NamingProbability(s.category[v * JointIdx(k) + JointIdx(d.reference)], k, jp.naming_noise));
    const double* p_o = &s.orientation[v * kOrientationCount];
    double p_relative = 0.0;
    for (int o = 0; o < kOrientationCount; ++o) {
      const auto orient = static_cast<Orientation>(o);
      // The relative reading: r' = the word; its frame probability averaged over the believed orientation.
      const double mean_r = knowledge.prior.Probability(scheme, Frame::kIntrinsic, terms.nature, orient, d.relation);
      const double pi_r = fronted ? IntrinsicPreference(mean_r, counts, jp.frame_prior_strength) : mean_r;
      p_relative += p_o[o] * (1.0 - pi_r);
      const double mean_i = knowledge.prior.Probability(scheme, Frame::kIntrinsic, terms.nature, orient,
                                                        terms.intrinsic_relative[JointIdx(o)]);
      const double pi_i = fronted ? IntrinsicPreference(mean_i, counts, jp.frame_prior_strength) : mean_i;
      p_intrinsic_frame[v][JointIdx(o)] = pi_i * p_o[o];
      log_intrinsic[v][JointIdx(o)] = SafeLog(pi_i * p_o[o]);
    }
    log_relative_frame[v] = SafeLog(p_relative);
  }
  const int directed_count = graph.DirectedEdgeCount();
  out.resize(JointIdx(directed_count * kInterpretationCount));
  for (int e = 0; e < directed_count; ++e) {
    const std::size_t a = JointIdx(graph.Located(e)), b = JointIdx(graph.Reference(e));
    const double base = log_located[a] + log_reference[b] + terms.log_proximity[JointIdx(e)];
    InterpretationScore* x = &out[JointIdx(e * kInterpretationCount)];
    x[0].relative = d.relation;
    x[0].rho = std::exp(log_relative_frame[b]) * terms.relative_fit[JointIdx(e)];
    x[0].score = base + log_relative_frame[b] + SafeLog(terms.relative_fit[JointIdx(e)]);
    for (int o = 0; o < kOrientationCount; ++o) {
      const double fit = terms.intrinsic_fit[JointIdx(e)][JointIdx(o)];
      x[o + 1].relative = terms.intrinsic_relative[JointIdx(o)];
      x[o + 1].rho = p_intrinsic_frame[b][JointIdx(o)] * fit;
      x[o + 1].score = base + log_intrinsic[b][JointIdx(o)] + SafeLog(fit);
    }
  }
  // A repeat of an earlier description read as the same pieces the same way counts once: it adds repeat_weight of
  // its score (0 by default), once however often it was told before.
  std::vector<std::size_t> repeated;
  for (const Match& m : parent.matches) {
    if (m.located_category != d.located || m.reference_category != d.reference || m.directed_edge < 0) continue;
    const std::size_t i = JointIdx(m.directed_edge * kInterpretationCount + m.interpretation);
    if (out[i].relative != m.relative || std::find(repeated.begin(), repeated.end(), i) != repeated.end()) continue;
    out[i].score *= jp.repeat_weight;
    repeated.push_back(i);
  }
}

void JointCategoryUpdate(const FurnitureGraph& graph, GraphState& state, const Description& d, const Match& match,
                         double naming_noise, double category_floor, const std::vector<Match>& earlier) {
  if (!CategoryUpdateAllowed(graph, state, d, match, category_floor, earlier)) return;
  const int k = graph.category_count;
  const int vertices[2] = {graph.Located(match.directed_edge), graph.Reference(match.directed_edge)};
  const int described[2] = {d.located, d.reference};
  const double other = k > 1 ? naming_noise / (k - 1) : 0.0;
  for (int i = 0; i < 2; ++i) {
    double* row = &state.category[JointIdx(vertices[i] * k)];
    double sum = 0.0;
    for (int c = 0; c < k; ++c) sum += row[c] *= c == described[i] ? 1.0 - naming_noise : other;
    if (sum > 0.0) {
      for (int c = 0; c < k; ++c) row[c] /= sum;
    }
  }
}

GraphState JointApplyMatch(const FurnitureGraph& graph, const GraphState& state, const Knowledge& knowledge,
                           const Description& d, const Match& match, const GroundingParams& params, bool categories,
                           const std::vector<Match>& earlier) {
  GraphState out = state;
  if (std::any_of(earlier.begin(), earlier.end(), [&](const Match& m) { return SameReading(m, match); })) return out;
  if (categories) JointCategoryUpdate(graph, out, d, match, params.joint.naming_noise, params.category_floor, earlier);
  Distribution4 relation{};
  relation[JointIdx(static_cast<int>(match.relative))] = 1.0;
  DampedUpdate(&out.relation[JointIdx(match.directed_edge * kRelationCount)], relation.data(), kRelationCount, params.sigma);
  if (FrameOf(match.interpretation) == Frame::kIntrinsic) {
    const Nature nature = knowledge.categories[d.reference].nature;
    const Distribution4& visual = graph.Visual(match.directed_edge);
    double* p_o = &out.orientation[JointIdx(graph.Reference(match.directed_edge) * kOrientationCount)];
    double sum = 0.0;
    for (int o = 0; o < kOrientationCount; ++o) {
      const Relation r = IntrinsicToRelative(d.relation, nature, static_cast<Orientation>(o));
      sum += p_o[o] *= Slacked(visual[JointIdx(static_cast<int>(r))], params.joint.edge_fit_slack);
    }
    if (sum > 0.0) {
      for (int o = 0; o < kOrientationCount; ++o) p_o[o] /= sum;
    }
  }
  return out;
}

}  // namespace anchordb::engine::grounding
