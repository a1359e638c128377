#include "engine/grounding/furniture_graph.h"

#include <algorithm>
#include <cmath>

#include "schema/error.h"

namespace anchordb::engine::grounding {

Eigen::Vector2d Viewpoint::ToViewer(const Eigen::Vector2d& d_map) const {
  const Eigen::Vector2d forward(std::cos(heading_rad), std::sin(heading_rad));
  const Eigen::Vector2d right(std::sin(heading_rad), -std::cos(heading_rad));
  return {d_map.dot(right), d_map.dot(forward)};
}

int FurnitureGraph::FindDirected(int located, int reference) const {
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (edges[e].a == located && edges[e].b == reference) return static_cast<int>(2 * e);
    if (edges[e].b == located && edges[e].a == reference) return static_cast<int>(2 * e + 1);
  }
  return -1;
}

int FurnitureGraph::VertexIndex(const std::string& id) const {
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

Distribution4 RelationFromOffset(const Eigen::Vector2d& d_V, double sharpness) {
  const double norm = d_V.norm();
  if (!(norm > 1e-9)) return {0.25, 0.25, 0.25, 0.25};
  const Eigen::Vector2d u = d_V / norm;
  // cos of the angle between the offset and each relation's direction (left, right, in front = towards the
  // viewer, behind = away from the viewer).
  const double cosines[4] = {-u.x(), u.x(), -u.y(), u.y()};
  Distribution4 p{};
  double sum = 0.0;
  for (int r = 0; r < 4; ++r) sum += p[static_cast<std::size_t>(r)] = std::exp(sharpness * cosines[r]);
  for (double& v : p) v /= sum;
  return p;
}

Distribution4 LineOfSightRelation(const Viewpoint& viewpoint, const Eigen::Vector2d& located_map,
                                  const Eigen::Vector2d& reference_map, double sharpness) {
  const Eigen::Vector2d sight = reference_map - viewpoint.position_m;
  Viewpoint along = viewpoint;
  if (sight.norm() > 1e-9) along.heading_rad = std::atan2(sight.y(), sight.x());
  return RelationFromOffset(along.ToViewer(located_map - reference_map), sharpness);
}

void SetLineOfSight(FurnitureGraph& graph, const Viewpoint& viewpoint, double sharpness) {
  for (Edge& e : graph.edges) {
    const Eigen::Vector2d& a = graph.vertices[static_cast<std::size_t>(e.a)].position_m;
    const Eigen::Vector2d& b = graph.vertices[static_cast<std::size_t>(e.b)].position_m;
    e.line_of_sight[0] = LineOfSightRelation(viewpoint, a, b, sharpness);
    e.line_of_sight[1] = LineOfSightRelation(viewpoint, b, a, sharpness);
  }
}

namespace {

Eigen::Vector2d HalfBox(const FurnitureInput& f) {
  const double c = std::abs(std::cos(f.yaw_rad)), s = std::abs(std::sin(f.yaw_rad));
  return 0.5 * Eigen::Vector2d(c * f.extent_m.x() + s * f.extent_m.y(), s * f.extent_m.x() + c * f.extent_m.y());
}

}  // namespace

double FootprintGap(const FurnitureInput& a, const FurnitureInput& b) {
  const Eigen::Vector2d reach = HalfBox(a) + HalfBox(b);
  const Eigen::Vector2d d = (a.position_m - b.position_m).cwiseAbs();
  return std::hypot(std::max(0.0, d.x() - reach.x()), std::max(0.0, d.y() - reach.y()));
}

FurnitureGraph BuildFurnitureGraph(const Viewpoint& viewpoint, const std::vector<FurnitureInput>& furniture,
                                   int category_count, const GraphParams& params) {
  if (furniture.size() < 2) {
    throw Error(ErrorCode::kUnprocessable, "a furniture graph needs at least two furniture pieces, got " +
                                               std::to_string(furniture.size()), "furniture");
  }
  FurnitureGraph g;
  g.category_count = category_count;
  const std::size_t k = static_cast<std::size_t>(category_count);
  for (std::size_t i = 0; i < furniture.size(); ++i) {
    const FurnitureInput& f = furniture[i];
    if (f.category.size() != k) {
      throw Error(ErrorCode::kInvalidArgument, "furniture '" + f.id + "' has " + std::to_string(f.category.size()) +
                                                   " category probabilities, expected " + std::to_string(k), "furniture");
    }
    g.vertices.push_back({f.id, f.position_m, f.extent_m, f.yaw_rad});
    g.initial.category.insert(g.initial.category.end(), f.category.begin(), f.category.end());
    for (int o = 0; o < kOrientationCount; ++o) g.initial.orientation.push_back(1.0 / kOrientationCount);
  }
  for (std::size_t i = 0; i < furniture.size(); ++i) {
    for (std::size_t j = i + 1; j < furniture.size(); ++j) {
      const double gap = FootprintGap(furniture[i], furniture[j]);
      if (gap > params.edge_max_gap_m) continue;
      Edge e;
      e.a = static_cast<int>(i);
      e.b = static_cast<int>(j);
      e.gap_m = gap;
      const Eigen::Vector2d d_V = viewpoint.ToViewer(furniture[i].position_m - furniture[j].position_m);
      e.visual[0] = RelationFromOffset(d_V, params.relation_sharpness);
      e.visual[1] = RelationFromOffset(-d_V, params.relation_sharpness);
      e.line_of_sight[0] = LineOfSightRelation(viewpoint, furniture[i].position_m, furniture[j].position_m, params.relation_sharpness);
      e.line_of_sight[1] = LineOfSightRelation(viewpoint, furniture[j].position_m, furniture[i].position_m, params.relation_sharpness);
      g.edges.push_back(e);
      for (const Distribution4& p : e.visual) g.initial.relation.insert(g.initial.relation.end(), p.begin(), p.end());
    }
  }
  if (g.edges.empty()) {
    throw Error(ErrorCode::kUnprocessable, "no two furniture pieces are within edge_max_gap_m = " +
                                               std::to_string(params.edge_max_gap_m) + " m of each other: the graph would have no edges",
                "furniture");
  }
  return g;
}

}  // namespace anchordb::engine::grounding
