#pragma once
// The furniture graph of thesis 5.3.2: one vertex per furniture piece with its category distribution p(f) and its
// orientation distribution p(o) (uniform at first), and an edge between every two pieces whose footprints are
// closer than a threshold, with a relation distribution p(r) for each direction, initialised softly from the
// pieces' positions as seen from a viewpoint. All relations are in the relative frame of that viewpoint.
//
// Frames: positions are in the map frame M (REP-103: x forward, y left) [m]; the viewer frame V has x_V to the
// viewer's right and y_V along the viewing direction (away from the viewer).
#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include "engine/grounding/knowledge.h"

namespace anchordb::engine::grounding {

// Where the scene is seen from: position p_MV [m] and viewing direction (yaw in M) [rad].
struct Viewpoint {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double heading_rad = 0.0;
  // The map-frame vector d_map expressed in the viewer frame (x right, y forward).
  Eigen::Vector2d ToViewer(const Eigen::Vector2d& d_map) const;
};

struct FurnitureInput {
  std::string id;                                    // vertex id (instance id or "v1", ...)
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // footprint centre in M [m]
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();    // footprint size along the piece's own axes [m]
  double yaw_rad = 0.0;                              // footprint rotation in M [rad]
  std::vector<double> category;                      // p(f), one entry per category of the table, sums to 1
};

struct GraphParams {
  double edge_max_gap_m = 1.5;      // an edge joins pieces whose footprints are at most this far apart [m]
  double relation_sharpness = 3.0;  // kappa of p(r) ∝ exp(kappa cos(angle to the relation's direction))
};

struct Vertex {
  std::string id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
};

using Distribution4 = std::array<double, 4>;

// An undirected edge {a, b}, a < b. Directed edge 2e is "a relative to b" (a located, b reference), 2e + 1 is
// "b relative to a".
struct Edge {
  int a = 0;
  int b = 0;
  double gap_m = 0.0;
  std::array<Distribution4, 2> visual{};  // p(r) from the geometry, per direction (indexed by Relation)
  // p(r) in the relative frame taken along the line of sight from the viewer to the reference piece (not along the
  // viewing direction), per direction: what the joint model (engine/grounding/joint_model.h) mixes into the fit of
  // a relative reading. Derived from the vertices and the viewpoint (SetLineOfSight), never stored.
  std::array<Distribution4, 2> line_of_sight{};
};

// The distributions that descriptions change: one copy per hypothesis.
struct GraphState {
  std::vector<double> category;     // vertices x categories, row-major: p(f)
  std::vector<double> orientation;  // vertices x 4 (indexed by Orientation): p(o)
  std::vector<double> relation;     // directed edges x 4 (indexed by Relation): p(r)
  bool operator==(const GraphState&) const = default;
};

struct FurnitureGraph {
  int category_count = 0;
  std::vector<Vertex> vertices;
  std::vector<Edge> edges;
  GraphState initial;

  int DirectedEdgeCount() const { return static_cast<int>(edges.size()) * 2; }
  int Located(int directed) const {
    const Edge& e = edges[static_cast<std::size_t>(directed / 2)];
    return directed % 2 == 0 ? e.a : e.b;
  }
  int Reference(int directed) const {
    const Edge& e = edges[static_cast<std::size_t>(directed / 2)];
    return directed % 2 == 0 ? e.b : e.a;
  }
  const Distribution4& Visual(int directed) const { return edges[static_cast<std::size_t>(directed / 2)].visual[directed % 2]; }
  // The directed edge with located vertex `located` and reference `reference`, or -1 when they share no edge.
  int FindDirected(int located, int reference) const;
  int VertexIndex(const std::string& id) const;  // -1 when unknown
};

// p(r) of a located object at offset d_V from its reference, in the viewer frame; uniform when d_V is zero.
Distribution4 RelationFromOffset(const Eigen::Vector2d& d_V, double sharpness);

// p(r) of a located piece at p_map relative to a reference at q_map, in the frame whose forward axis is the line of sight
// from the viewpoint's position to q_map (the viewing direction when q_map is at the viewer).
Distribution4 LineOfSightRelation(const Viewpoint& viewpoint, const Eigen::Vector2d& located_map,
                                  const Eigen::Vector2d& reference_map, double sharpness);

// Fills every edge's line_of_sight from the vertices' positions (BuildFurnitureGraph does; a graph read back from
// its stored form needs it again).
void SetLineOfSight(FurnitureGraph& graph, const Viewpoint& viewpoint, double sharpness);

// Shortest distance between the two pieces' footprints (axis-aligned boxes around the rotated extents) [m].
double FootprintGap(const FurnitureInput& a, const FurnitureInput& b);

// Builds the graph; p(o) starts uniform. Throws Error(kUnprocessable) when there are fewer than two pieces or no
// two pieces are close enough for an edge, Error(kInvalidArgument) when a p(f) has the wrong length.
FurnitureGraph BuildFurnitureGraph(const Viewpoint& viewpoint, const std::vector<FurnitureInput>& furniture,
                                   int category_count, const GraphParams& params);

}  // namespace anchordb::engine::grounding
