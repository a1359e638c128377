#include "tests/eval/grounding_adversarial.h"
#include "tests/eval/seeded_rng.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <cstdio>

#include "engine/grounding/joint_model.h"
#include "engine/grounding/orientation_prior.h"

namespace anchordb::eval::adversarial {

using namespace engine::grounding;
using eval::SeededRng;

namespace {

using Rng = SeededRng;

// The room: x 1-6.5 m, y -2.5-2.5 m; the viewer stands at (1.3, 0) looking along +x.
constexpr double kRoomX0 = 1.0, kRoomX1 = 6.5, kRoomHalfY = 2.5;
const Eigen::Vector2d kViewer(1.3, 0.0);

struct Piece {
  int category = 0;
  Eigen::Vector2d position_m, extent_m;  // extent along the piece's own x (depth, front-back) and y (width)
  double yaw_rad = 0.0;                  // the piece's front points along (cos yaw, sin yaw)
};

Eigen::Vector2d Footprint(const std::string& id) {
  if (id == "sofa") return {0.9, 1.8};
  if (id == "armchair") return {0.8, 0.8};
  if (id == "chair") return {0.5, 0.5};
  if (id == "shelf") return {0.4, 1.0};
  if (id == "wardrobe") return {0.6, 1.2};
  if (id == "cupboard") return {0.5, 1.0};
  if (id == "chest_of_drawers") return {0.5, 0.9};
  if (id == "table") return {0.8, 1.2};
  return {0.4, 0.4};
}

// The word for `d` (located - reference) in a frame whose forward axis is `forward` and whose left is `left`.
Relation WordIn(const Eigen::Vector2d& d, const Eigen::Vector2d& forward, const Eigen::Vector2d& left) {
  const double f = d.dot(forward), l = d.dot(left);
  if (std::abs(f) >= std::abs(l)) return f >= 0 ? Relation::kInFrontOf : Relation::kBehind;
  return l >= 0 ? Relation::kLeftOf : Relation::kRightOf;
}

// Relative frame along the line of sight from the viewer to the reference: "in front of" = towards the viewer.
Relation LineOfSightWord(const Piece& loc, const Piece& ref) {
  const Eigen::Vector2d sight = (ref.position_m - kViewer).normalized();
  return WordIn(loc.position_m - ref.position_m, -sight, Eigen::Vector2d(-sight.y(), sight.x()));
}

// The reference's own frame: in front of = on its front side; left as if sitting in it (vehicle) or standing before
// it facing it (opposite; none pieces have no intrinsic frame and are read like vehicles).
Relation IntrinsicWord(const Piece& loc, const Piece& ref, Nature nature) {
  const Eigen::Vector2d f(std::cos(ref.yaw_rad), std::sin(ref.yaw_rad));
  const Eigen::Vector2d left = nature == Nature::kOpposite ? Eigen::Vector2d(f.y(), -f.x()) : Eigen::Vector2d(-f.y(), f.x());
  return WordIn(loc.position_m - ref.position_m, f, left);
}

struct Room {
  std::vector<Piece> pieces;
  struct Said {
    int located = 0, reference = 0;
    Relation word = Relation::kLeftOf;
    bool intrinsic = false;
  };
  std::vector<Said> descriptions;
  int misclassified = 0;
};

Room MakeRoom(std::uint64_t seed, Speaker speaker, const Knowledge& k) {
  Rng rng(seed * 1000003 + static_cast<std::uint64_t>(speaker) * 7777 + 3);
  Room room;
  const int count = 6 + rng.Below(4);
  std::vector<int> cats;
  const int dup = rng.Below(k.categories.size());
  const int copies = 2 + rng.Below(2);
  for (int i = 0; i < copies; ++i) cats.push_back(dup);
  while (static_cast<int>(cats.size()) < count) cats.push_back(rng.Below(k.categories.size()));
  for (int c : cats) {
    Piece p;
    p.category = c;
    p.extent_m = Footprint(k.categories[c].id);
    const Nature nature = k.categories[c].nature;
    for (int attempt = 0; attempt < 200; ++attempt) {
      if (nature == Nature::kOpposite) {
        // Against the east, north or south wall, facing into the room.
        const int wall = rng.Below(3);
        const double half_depth = 0.5 * p.extent_m.x();
        if (wall == 0) p.position_m = {kRoomX1 - half_depth, rng.Uniform(-2.0, 2.0)}, p.yaw_rad = M_PI;
        else if (wall == 1) p.position_m = {rng.Uniform(2.5, 6.0), kRoomHalfY - half_depth}, p.yaw_rad = -M_PI / 2;
        else p.position_m = {rng.Uniform(2.5, 6.0), -kRoomHalfY + half_depth}, p.yaw_rad = M_PI / 2;
      } else {
        p.position_m = {rng.Uniform(2.3, 6.0), rng.Uniform(-2.0, 2.0)};
        p.yaw_rad = rng.Uniform(-M_PI, M_PI);  // any orientation
      }
      FurnitureInput a{"", p.position_m, p.extent_m, p.yaw_rad, {}};
      const bool clear = std::all_of(room.pieces.begin(), room.pieces.end(), [&](const Piece& q) {
        return FootprintGap(a, FurnitureInput{"", q.position_m, q.extent_m, q.yaw_rad, {}}) >= 0.25;
      });
      if (clear) break;
    }
    room.pieces.push_back(p);
  }
  double p_intrinsic = 0.0;
  switch (speaker) {
    case Speaker::kRelative: p_intrinsic = rng.Uniform(0.0, 0.1); break;
    case Speaker::kMixed: p_intrinsic = rng.Uniform(0.3, 0.6); break;
    case Speaker::kIntrinsic: p_intrinsic = rng.Uniform(0.7, 0.95); break;
  }
  const int wanted = 10 + rng.Below(11);
  const int n = static_cast<int>(room.pieces.size());
  const auto fi = [&](int i) {
    const Piece& q = room.pieces[static_cast<std::size_t>(i)];
    return FurnitureInput{"", q.position_m, q.extent_m, q.yaw_rad, {}};
  };
  for (int t = 0; t < wanted; ++t) {
    const int loc = rng.Below(n);
    int ref = -1;
    double best = GraphParams{}.edge_max_gap_m;
    for (int j = 0; j < n; ++j) {  // the nearest neighbour
      if (j == loc) continue;
      const double gap = FootprintGap(fi(loc), fi(j));
      if (gap <= best) best = gap, ref = j;
    }
    if (ref < 0) continue;
    const Piece& l = room.pieces[static_cast<std::size_t>(loc)];
    const Piece& r = room.pieces[static_cast<std::size_t>(ref)];
    const Nature nature = k.categories[r.category].nature;
    const bool intrinsic = nature != Nature::kNone && rng.Uniform(0.0, 1.0) < p_intrinsic;
    room.descriptions.push_back({loc, ref, intrinsic ? IntrinsicWord(l, r, nature) : LineOfSightWord(l, r), intrinsic});
  }
  room.misclassified = room.descriptions.empty() ? 0 : room.descriptions[static_cast<std::size_t>(rng.Below(static_cast<int>(room.descriptions.size())))].located;
  return room;
}

std::vector<double> Visual(const Room& room, int quality, int k, std::uint64_t seed) {
  Rng rng(seed * 31 + static_cast<std::uint64_t>(quality) * 101 + 9);
  std::vector<double> out;
  for (std::size_t i = 0; i < room.pieces.size(); ++i) {
    const int truth = room.pieces[i].category;
    int other = rng.Below(k - 1);
    if (other >= truth) ++other;
    const bool wrong = quality == 1 && static_cast<int>(i) == room.misclassified;
    const double p_true = wrong ? rng.Uniform(0.20, 0.30) : quality == 0 ? rng.Uniform(0.5, 0.7) : rng.Uniform(0.40, 0.55);
    const double p_other = wrong ? rng.Uniform(0.35, 0.45) : rng.Uniform(0.05, 0.2);
    std::vector<double> d(static_cast<std::size_t>(k), (1.0 - p_true - p_other) / (k - 2));
    d[static_cast<std::size_t>(truth)] = p_true;
    d[static_cast<std::size_t>(other)] = p_other;
    out.insert(out.end(), d.begin(), d.end());
  }
  return out;
}

// The occupancy layer of the room: its walls and the pieces' footprints, 5 cm cells.
engine::OccupancyGrid Occupancy(const Room& room) {
  GridGeometry g;
  g.resolution_m = 0.05;
  g.origin_x_m = kRoomX0 - 0.2;
  g.origin_y_m = -kRoomHalfY - 0.2;
  g.width_cells = static_cast<int>((kRoomX1 - kRoomX0 + 0.4) / g.resolution_m);
  g.height_cells = static_cast<int>((2 * kRoomHalfY + 0.4) / g.resolution_m);
  engine::OccupancyGrid grid(g, 0);
  for (int iy = 0; iy < g.height_cells; ++iy) {
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
      bool occupied = c.x() < kRoomX0 || c.x() > kRoomX1 || std::abs(c.y()) > kRoomHalfY;
      for (const Piece& p : room.pieces) {
        const Eigen::Vector2d d = c - p.position_m;
        const double cs = std::cos(p.yaw_rad), sn = std::sin(p.yaw_rad);
        const Eigen::Vector2d local(cs * d.x() + sn * d.y(), -sn * d.x() + cs * d.y());
        occupied |= std::abs(local.x()) <= 0.5 * p.extent_m.x() && std::abs(local.y()) <= 0.5 * p.extent_m.y();
      }
      grid.at(ix, iy) = occupied ? 100 : 0;
    }
  }
  return grid;
}

}  // namespace

const char* SpeakerName(Speaker s) { return s == Speaker::kRelative ? "relative" : s == Speaker::kMixed ? "mixed" : "intrinsic"; }
const char* ModelName(Model m) { return m == Model::kThesis ? "thesis model" : m == Model::kIssue17 ? "issue 17" : "joint"; }

GroundingParams JointOptions() {
  GroundingParams p;
  p.model = engine::grounding::Model::kJoint;
  p.ambiguity_margin = 0.3;
  p.category_floor = 0.05;
  return p;
}

namespace {

GroundingParams ParamsOf(Model model) {
  if (model == Model::kJoint) return JointOptions();
  GroundingParams p;
  if (model == Model::kIssue17) {
    p.ambiguity_margin = 0.02;
    p.category_floor = 0.05;
  }
  return p;
}

RoomResult Run(std::uint64_t seed, Speaker speaker, int quality, const GroundingParams* given, Model model, bool trace = false) {
  const Knowledge& k = DefaultKnowledge();
  const int kc = k.categories.size();
  const Room room = MakeRoom(seed, speaker, k);
  const std::vector<double> visual = Visual(room, quality, kc, seed * 3 + static_cast<std::uint64_t>(speaker));
  std::vector<FurnitureInput> furniture;
  for (std::size_t i = 0; i < room.pieces.size(); ++i) {
    const Piece& p = room.pieces[i];
    furniture.push_back({"v" + std::to_string(i), p.position_m, p.extent_m, p.yaw_rad,
                         std::vector<double>(visual.begin() + static_cast<std::ptrdiff_t>(i * kc),
                                             visual.begin() + static_cast<std::ptrdiff_t>((i + 1) * kc))});
  }
  const Viewpoint view{kViewer, 0.0};
  FurnitureGraph graph = BuildFurnitureGraph(view, furniture, kc, GraphParams{});
  const GroundingParams params = given ? *given : ParamsOf(model);
  if (given || model != Model::kThesis) {
    const engine::OccupancyGrid occupancy = Occupancy(room);
    graph.initial.orientation = RoomOrientationPrior(view, furniture, k.categories, RoomLayout{&occupancy, {}});
  }
  HypothesisSet set = InitialHypotheses(graph);
  std::vector<Room::Said> grounded;
  for (const Room::Said& s : room.descriptions) {
    if (graph.FindDirected(s.located, s.reference) < 0) continue;  // no edge: the model cannot match it
    set = Ground(graph, k, set, {room.pieces[static_cast<std::size_t>(s.located)].category, s.word,
                                 room.pieces[static_cast<std::size_t>(s.reference)].category}, params);
    grounded.push_back(s);
  }
  RoomResult r;
  const Hypothesis& best = set.ranked.front();
  r.descriptions = static_cast<int>(grounded.size());
  for (std::size_t t = 0; t < grounded.size(); ++t) {
    const Room::Said& s = grounded[t];
    const int a = graph.Located(best.matches[t].directed_edge), b = graph.Reference(best.matches[t].directed_edge);
    const Piece &pa = room.pieces[static_cast<std::size_t>(a)], &pb = room.pieces[static_cast<std::size_t>(b)];
    const bool same = a == s.located && b == s.reference;
    const bool equivalent = pa.category == room.pieces[static_cast<std::size_t>(s.located)].category &&
                            pb.category == room.pieces[static_cast<std::size_t>(s.reference)].category &&
                            (LineOfSightWord(pa, pb) == s.word ||
                             (k.categories[pb.category].nature != Nature::kNone && IntrinsicWord(pa, pb, k.categories[pb.category].nature) == s.word));
    r.right += same || equivalent;
    if (trace) {
      const Description d{room.pieces[static_cast<std::size_t>(s.located)].category, s.word, room.pieces[static_cast<std::size_t>(s.reference)].category};
      const JointDescriptionTerms terms = JointTerms(graph, k, d, params.joint);
      const auto show = [&](int e) {
        const std::size_t i = static_cast<std::size_t>(e);
        std::fprintf(stderr, " [prox %.2f rel %.2f int %.2f %.2f %.2f %.2f]", terms.log_proximity[i], terms.relative_fit[i],
                     terms.intrinsic_fit[i][0], terms.intrinsic_fit[i][1], terms.intrinsic_fit[i][2], terms.intrinsic_fit[i][3]);
      };
      show(graph.FindDirected(s.located, s.reference));
      show(best.matches[t].directed_edge);
      std::fprintf(stderr, "  %2zu: %s v%d %s v%d (frame %s) -> v%d v%d interp %d step %.2f%s%s\n", t, k.categories[room.pieces[static_cast<std::size_t>(s.located)].category].id.c_str(),
                   s.located, RelationId(s.word), s.reference, s.intrinsic ? "I" : "R", a, b, best.matches[t].interpretation,
                   best.matches[t].score, same || equivalent ? "" : "  WRONG",
                   std::any_of(set.held.begin(), set.held.end(), [&](const HeldStep& h) { return h.step == static_cast<int>(t); }) ? " held" : "");
    }
  }
  r.graph_right = true;
  for (std::size_t v = 0; v < room.pieces.size(); ++v) {
    const double* row = &best.state.category[v * static_cast<std::size_t>(kc)];
    const int top = static_cast<int>(std::max_element(row, row + kc) - row);
    r.graph_right &= top == room.pieces[v].category;
    if (trace) {
      const double* seen = &graph.initial.category[v * static_cast<std::size_t>(kc)];
      std::fprintf(stderr, "  v%zu %s at (%.2f, %.2f) yaw %.0f: seen p(true) %.2f, end %s %.2f%s\n", v, k.categories[room.pieces[v].category].id.c_str(),
                   room.pieces[v].position_m.x(), room.pieces[v].position_m.y(), room.pieces[v].yaw_rad * 180 / M_PI,
                   seen[room.pieces[v].category], k.categories[top].id.c_str(), row[top], top == room.pieces[v].category ? "" : "  WRONG");
    }
  }
  return r;
}

}  // namespace

RoomResult RunRoom(std::uint64_t seed, Speaker speaker, int quality, Model model) {
  return Run(seed, speaker, quality, nullptr, model);
}

RoomResult RunRoom(std::uint64_t seed, Speaker speaker, int quality, const GroundingParams& params) {
  return Run(seed, speaker, quality, &params, Model::kJoint);
}

void TraceRoom(std::uint64_t seed, Speaker speaker, int quality, const GroundingParams& params) {
  Run(seed, speaker, quality, &params, Model::kJoint, true);
}

double Table::DescriptionRate(Model m) const {
  const Cell a = Over(m, 0), b = Over(m, 1);
  return a.descriptions + b.descriptions ? double(a.right + b.right) / double(a.descriptions + b.descriptions) : 0.0;
}

Cell Table::Over(Model m, int quality) const {
  Cell all;
  for (const Cell& c : cells[static_cast<int>(m)][quality]) {
    all.rooms += c.rooms;
    all.graphs_right += c.graphs_right;
    all.descriptions += c.descriptions;
    all.right += c.right;
    all.worst_room_rate = std::min(all.worst_room_rate, c.worst_room_rate);
  }
  return all;
}

Table Evaluate(int rooms, std::uint64_t first_seed, const std::vector<Model>& models, const GroundingParams* joint) {
  Table table;
  for (const Model model : models) {
    const int m = static_cast<int>(model);
    for (int q = 0; q < 2; ++q) {
      for (int s = 0; s < 3; ++s) {
        Cell& cell = table.cells[m][q][s];
        for (int i = 0; i < rooms; ++i) {
          const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
          const RoomResult r = model == Model::kJoint && joint ? RunRoom(seed, static_cast<Speaker>(s), q, *joint)
                                                               : RunRoom(seed, static_cast<Speaker>(s), q, model);
          ++cell.rooms;
          cell.graphs_right += r.graph_right;
          cell.descriptions += r.descriptions;
          cell.right += r.right;
          if (r.descriptions > 0) cell.worst_room_rate = std::min(cell.worst_room_rate, double(r.right) / r.descriptions);
        }
      }
    }
  }
  return table;
}

}  // namespace anchordb::eval::adversarial
