#include "tests/eval/grounding_eval.h"
#include "tests/eval/seeded_rng.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace anchordb::eval {

using namespace engine::grounding;

namespace {

using Rng = SeededRng;

constexpr double kSpacingM = 1.7;          // grid spacing, across and along the line of sight
constexpr double kFirstRowM = 2.0;         // distance of the nearest row from the viewer
constexpr double kJitterM = 0.04;
constexpr double kIntrinsicPreference = 0.85;

// Footprint [m] (depth along the line of sight, width across it) of each default category.
Eigen::Vector2d Footprint(const std::string& id) {
  if (id == "sofa") return {0.9, 1.6};
  if (id == "armchair") return {0.8, 0.8};
  if (id == "chair") return {0.5, 0.5};
  if (id == "shelf") return {0.4, 1.0};
  if (id == "wardrobe") return {0.6, 1.2};
  if (id == "cupboard") return {0.5, 1.0};
  if (id == "chest_of_drawers") return {0.5, 0.9};
  if (id == "table") return {0.8, 1.2};
  return {0.4, 0.4};  // plant, stool, anything else
}

}  // namespace

const char* QualityName(Quality q) { return q == Quality::kA ? "A" : q == Quality::kB ? "B" : "C"; }
const char* SpeakerName(Speaker s) {
  return s == Speaker::kRelative ? "relative" : s == Speaker::kPrior ? "prior" : "intrinsic";
}
const char* ConditionName(Condition c) {
  return c == Condition::kAdaptation ? "adaptation" : c == Condition::kNoAdaptation ? "no adaptation" : "uniform prior";
}

Participant MakeParticipant(std::uint64_t seed, Speaker speaker, const Knowledge& knowledge) {
  Rng rng(seed * 7919 + static_cast<std::uint64_t>(speaker) * 104729 + 17);
  Participant p;
  p.seed = seed;
  p.speaker = speaker;
  p.view = Viewpoint{{0.0, 0.0}, 0.0};  // looking along map +x; map +y is the viewer's left
  const int k = knowledge.categories.size();
  const int count = 6 + rng.Below(3);
  // Cells of a 3 x 3 grid: column -1 (viewer's left) .. 1, row 0 (nearest) .. 2.
  std::vector<int> cells(9);
  std::iota(cells.begin(), cells.end(), 0);
  rng.Shuffle(cells);
  cells.resize(static_cast<std::size_t>(count));
  std::sort(cells.begin(), cells.end());
  std::vector<int> categories(static_cast<std::size_t>(k));
  std::iota(categories.begin(), categories.end(), 0);
  rng.Shuffle(categories);
  categories.resize(static_cast<std::size_t>(count));
  // Half of the scenes hold two pieces of one category (the thesis' living room had two armchairs).
  if (rng.Chance(0.5)) categories.back() = categories[static_cast<std::size_t>(rng.Below(count - 1))];
  for (int i = 0; i < count; ++i) {
    const int cell = cells[static_cast<std::size_t>(i)];
    const int column = cell % 3 - 1, row = cell / 3;
    TruePiece piece;
    piece.category = categories[static_cast<std::size_t>(i)];
    const Nature nature = knowledge.categories[piece.category].nature;
    // Opposite objects stand at walls and are never seen from behind (thesis 5.2.1).
    piece.orientation = static_cast<Orientation>(nature == Nature::kOpposite ? std::vector<int>{0, 1, 2}[static_cast<std::size_t>(rng.Below(3))]
                                                                              : rng.Below(4));
    piece.position_m = {kFirstRowM + row * kSpacingM + rng.Uniform(-kJitterM, kJitterM),
                        -column * kSpacingM + rng.Uniform(-kJitterM, kJitterM)};
    piece.extent_m = Footprint(knowledge.categories[piece.category].id);
    p.pieces.push_back(piece);
  }
  // Neighbouring pairs (same row or column, adjacent cells) that the graph joins by an edge, both directions.
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j < count; ++j) {
      if (i == j) continue;
      const int ci = cells[static_cast<std::size_t>(i)], cj = cells[static_cast<std::size_t>(j)];
      const bool adjacent = (ci / 3 == cj / 3 && std::abs(ci % 3 - cj % 3) == 1) || (ci % 3 == cj % 3 && std::abs(ci / 3 - cj / 3) == 1);
      if (!adjacent) continue;
      FurnitureInput a{"", p.pieces[static_cast<std::size_t>(i)].position_m, p.pieces[static_cast<std::size_t>(i)].extent_m, 0.0, {}};
      FurnitureInput b{"", p.pieces[static_cast<std::size_t>(j)].position_m, p.pieces[static_cast<std::size_t>(j)].extent_m, 0.0, {}};
      if (FootprintGap(a, b) <= GraphParams{}.edge_max_gap_m) pairs.emplace_back(i, j);
    }
  }
  const int wanted = 12 + rng.Below(9);
  std::vector<std::pair<int, int>> order;
  while (static_cast<int>(order.size()) < wanted && !pairs.empty()) {
    std::vector<std::pair<int, int>> round = pairs;
    rng.Shuffle(round);
    for (const auto& pr : round) {
      if (static_cast<int>(order.size()) < wanted) order.push_back(pr);
    }
  }
  for (const auto& [loc, ref] : order) {
    const TruePiece& l = p.pieces[static_cast<std::size_t>(loc)];
    const TruePiece& r = p.pieces[static_cast<std::size_t>(ref)];
    const Eigen::Vector2d d = p.view.ToViewer(l.position_m - r.position_m);
    const Relation seen = std::abs(d.x()) > std::abs(d.y()) ? (d.x() < 0 ? Relation::kLeftOf : Relation::kRightOf)
                                                            : (d.y() < 0 ? Relation::kInFrontOf : Relation::kBehind);
    const Nature nature = knowledge.categories[r.category].nature;
    TrueDescription td;
    td.located = loc;
    td.reference = ref;
    td.frames_differ = !FramePrior::FramesCoincide(nature, r.orientation, seen);
    bool intrinsic = false;
    switch (speaker) {
      case Speaker::kRelative: break;
      case Speaker::kPrior:
        intrinsic = rng.Chance(knowledge.prior.Probability(Scheme::kStatistical, Frame::kIntrinsic, nature, r.orientation, seen));
        break;
      case Speaker::kIntrinsic: intrinsic = nature != Nature::kNone && rng.Chance(kIntrinsicPreference); break;
    }
    td.frame = intrinsic ? Frame::kIntrinsic : Frame::kRelative;
    td.word = intrinsic ? RelativeToIntrinsic(seen, nature, r.orientation) : seen;
    p.descriptions.push_back(td);
  }
  // The piece the poorer visual analyses get wrong: one that is talked about.
  std::vector<int> described;
  for (const TrueDescription& td : p.descriptions) {
    described.push_back(td.located);
    described.push_back(td.reference);
  }
  std::sort(described.begin(), described.end());
  described.erase(std::unique(described.begin(), described.end()), described.end());
  p.misclassified = described.empty() ? 0 : described[static_cast<std::size_t>(rng.Below(static_cast<int>(described.size())))];
  return p;
}

std::vector<std::vector<double>> VisualCategories(const Participant& p, Quality q, int category_count) {
  Rng rng(p.seed * 31337 + static_cast<std::uint64_t>(p.speaker) * 65537 + static_cast<std::uint64_t>(q) * 257 + 5);
  std::vector<std::vector<double>> out;
  for (std::size_t i = 0; i < p.pieces.size(); ++i) {
    const int truth = p.pieces[i].category;
    std::vector<double> dist(static_cast<std::size_t>(category_count), 0.0);
    int other = rng.Below(category_count - 1);
    if (other >= truth) ++other;
    const bool wrong = q != Quality::kA && static_cast<int>(i) == p.misclassified;
    double p_true = 0.0, p_other = 0.0;
    switch (q) {
      case Quality::kA: p_true = rng.Uniform(0.50, 0.70), p_other = rng.Uniform(0.05, 0.15); break;
      case Quality::kB:
        if (wrong) p_other = rng.Uniform(0.35, 0.45), p_true = rng.Uniform(0.20, 0.30);
        else p_true = rng.Uniform(0.40, 0.55), p_other = rng.Uniform(0.10, 0.20);
        break;
      case Quality::kC:
        if (wrong) p_other = rng.Uniform(0.50, 0.65), p_true = rng.Uniform(0.03, 0.08);
        else p_true = rng.Uniform(0.22, 0.35), p_other = rng.Uniform(0.10, 0.20);
        break;
    }
    dist[static_cast<std::size_t>(truth)] = p_true;
    dist[static_cast<std::size_t>(other)] = p_other;
    std::vector<double> w(static_cast<std::size_t>(category_count), 0.0);
    double w_sum = 0.0;
    for (int c = 0; c < category_count; ++c) {
      if (c == truth || c == other) continue;
      w_sum += w[static_cast<std::size_t>(c)] = rng.Uniform(0.2, 1.0);
    }
    const double rest = 1.0 - p_true - p_other;
    for (int c = 0; c < category_count; ++c) {
      if (c != truth && c != other) dist[static_cast<std::size_t>(c)] = rest * w[static_cast<std::size_t>(c)] / w_sum;
    }
    out.push_back(dist);
  }
  return out;
}

double MeanEntropyBits(const std::vector<std::vector<double>>& distributions) {
  double total = 0.0;
  for (const auto& d : distributions) {
    for (double v : d) total -= v > 0.0 ? v * std::log2(v) : 0.0;
  }
  return distributions.empty() ? 0.0 : total / static_cast<double>(distributions.size());
}

TrialResult RunTrial(const Participant& p, Quality q, Condition c, const Knowledge& knowledge, const EvalOptions& options) {
  const int k = knowledge.categories.size();
  const auto visual = VisualCategories(p, q, k);
  std::vector<FurnitureInput> furniture;
  for (std::size_t i = 0; i < p.pieces.size(); ++i) {
    furniture.push_back({"v" + std::to_string(i), p.pieces[i].position_m, p.pieces[i].extent_m, 0.0, visual[i]});
  }
  const FurnitureGraph graph = BuildFurnitureGraph(p.view, furniture, k, GraphParams{});
  GroundingParams params;
  params.model = options.model;
  params.joint = options.joint;
  params.n_best = options.n_best;
  params.sigma = options.sigma;
  params.ambiguity_margin = options.ambiguity_margin;
  params.category_floor = options.category_floor;
  switch (c) {
    case Condition::kAdaptation: params.schemes = {Scheme::kStatistical, Scheme::kRelative, Scheme::kIntrinsic}; break;
    case Condition::kNoAdaptation: params.schemes = {Scheme::kStatistical}; break;
    case Condition::kUniform: params.schemes = {Scheme::kUniform}; break;
  }
  HypothesisSet set = InitialHypotheses(graph);
  TrialResult r;
  for (const TrueDescription& td : p.descriptions) {
    const Description d{p.pieces[static_cast<std::size_t>(td.located)].category, td.word,
                        p.pieces[static_cast<std::size_t>(td.reference)].category};
    set = Ground(graph, knowledge, set, d, params);
    r.intrinsic_descriptions += td.frame == Frame::kIntrinsic && td.frames_differ;
    const int step = set.step - 1;
    const bool held = std::any_of(set.held.begin(), set.held.end(), [&](const HeldStep& h) { return h.step == step; });
    const bool wrong = set.ranked.front().matches.back().directed_edge != graph.FindDirected(td.located, td.reference);
    r.held += held;
    r.held_wrong += held && wrong;
    r.unheld_wrong += !held && wrong;
  }
  const Hypothesis& best = set.ranked.front();
  r.descriptions = static_cast<int>(p.descriptions.size());
  for (std::size_t t = 0; t < p.descriptions.size(); ++t) {
    const TrueDescription& td = p.descriptions[t];
    r.descriptions_correct += best.matches[t].directed_edge == graph.FindDirected(td.located, td.reference);
  }
  r.sequence_correct = r.descriptions_correct == r.descriptions;
  const auto argmax = [&](int v) {
    const double* row = &best.state.category[static_cast<std::size_t>(v * k)];
    return static_cast<int>(std::max_element(row, row + k) - row);
  };
  for (std::size_t v = 0; v < p.pieces.size(); ++v) {
    ++r.vertices;
    r.vertices_right += argmax(static_cast<int>(v)) == p.pieces[v].category;
    if (knowledge.categories[p.pieces[v].category].nature == Nature::kNone) continue;
    ++r.fronted;
    const double* o = &best.state.orientation[v * kOrientationCount];
    const int top = static_cast<int>(std::max_element(o, o + kOrientationCount) - o);
    const bool unique = std::count(o, o + kOrientationCount, o[top]) == 1;
    r.orientations_right += unique && top == static_cast<int>(p.pieces[v].orientation);
  }
  const int m = p.misclassified;
  const double* start = visual[static_cast<std::size_t>(m)].data();
  r.misclassified_wrong_at_start = static_cast<int>(std::max_element(start, start + k) - start) != p.pieces[static_cast<std::size_t>(m)].category;
  r.misclassified_right = argmax(m) == p.pieces[static_cast<std::size_t>(m)].category;
  for (int rank : best.lineage_ranks) r.worst_rank_reverted = std::max(r.worst_rank_reverted, rank + 1);
  return r;
}

void Tally::Add(const TrialResult& r) {
  descriptions += r.descriptions;
  descriptions_correct += r.descriptions_correct;
  ++sequences;
  sequences_correct += r.sequence_correct;
  vertices += r.vertices;
  vertices_right += r.vertices_right;
  fronted += r.fronted;
  orientations_right += r.orientations_right;
  if (r.misclassified_wrong_at_start) {
    ++misclassified;
    misclassified_corrected += r.misclassified_right;
  }
  worst_rank_reverted = std::max(worst_rank_reverted, r.worst_rank_reverted);
  held += r.held;
  held_wrong += r.held_wrong;
  unheld_wrong += r.unheld_wrong;
}

Tally Evaluation::Over(Quality q, Condition c) const {
  Tally all;
  for (const Tally& t : tallies[static_cast<int>(q)][static_cast<int>(c)]) {
    all.descriptions += t.descriptions;
    all.descriptions_correct += t.descriptions_correct;
    all.sequences += t.sequences;
    all.sequences_correct += t.sequences_correct;
    all.vertices += t.vertices;
    all.vertices_right += t.vertices_right;
    all.fronted += t.fronted;
    all.orientations_right += t.orientations_right;
    all.misclassified += t.misclassified;
    all.misclassified_corrected += t.misclassified_corrected;
    all.worst_rank_reverted = std::max(all.worst_rank_reverted, t.worst_rank_reverted);
    all.held += t.held;
    all.held_wrong += t.held_wrong;
    all.unheld_wrong += t.unheld_wrong;
  }
  return all;
}

Evaluation Evaluate(int participants_per_speaker, std::uint64_t first_seed, const EvalOptions& options) {
  const Knowledge& knowledge = DefaultKnowledge();
  Evaluation e;
  e.participants_per_speaker = participants_per_speaker;
  double entropy[3] = {0, 0, 0};
  int count = 0;
  for (int s = 0; s < 3; ++s) {
    for (int i = 0; i < participants_per_speaker; ++i) {
      const Participant p = MakeParticipant(first_seed + static_cast<std::uint64_t>(i), static_cast<Speaker>(s), knowledge);
      ++count;
      for (int q = 0; q < 3; ++q) {
        entropy[q] += MeanEntropyBits(VisualCategories(p, static_cast<Quality>(q), knowledge.categories.size()));
        for (int c = 0; c < 3; ++c) {
          e.tallies[q][c][s].Add(RunTrial(p, static_cast<Quality>(q), static_cast<Condition>(c), knowledge, options));
        }
      }
    }
  }
  for (int q = 0; q < 3; ++q) e.entropy_bits[q] = count ? entropy[q] / count : 0.0;
  return e;
}

}  // namespace anchordb::eval
