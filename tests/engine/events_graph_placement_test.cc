// Where a thing stands among the furniture of a graph (engine/events/graph_placement.h): on a piece inside its
// footprint, otherwise the relation seen from the viewpoint in the frame the listener prefers.
#include "engine/events/graph_placement.h"

#include <gtest/gtest.h>

namespace anchordb::engine {
namespace events_graph_placement_test {

namespace g = grounding;

struct Scene {
  g::FurnitureGraph graph;
  g::HypothesisSet set;
  g::Viewpoint viewpoint;
};

// A table (index of "table") in front of a sofa, seen from the origin looking along +x.
Scene TableAndSofa() {
  const g::Knowledge& k = g::DefaultKnowledge();
  const int n = k.categories.size();
  std::vector<double> table(static_cast<std::size_t>(n), 0.0), sofa(static_cast<std::size_t>(n), 0.0);
  table[static_cast<std::size_t>(k.categories.IndexOfId("table"))] = 1.0;
  sofa[static_cast<std::size_t>(k.categories.IndexOfId("sofa"))] = 1.0;
  Scene s;
  s.graph = g::BuildFurnitureGraph(s.viewpoint, {{"t", {2.8, 0.0}, {0.6, 1.0}, 0.0, table}, {"s", {4.0, 0.0}, {0.9, 2.0}, 0.0, sofa}}, n, {});
  s.set = g::InitialHypotheses(s.graph);
  return s;
}

TEST(EventsGraphPlacement, OnThePieceWhoseFootprintHoldsTheThing) {
  const Scene s = TableAndSofa();
  const GraphPlacement p = PlaceInGraph(s.graph, g::DefaultKnowledge(), s.set.ranked.front(), s.viewpoint, 3.0, {2.9, 0.2, 0.75});
  EXPECT_EQ(p.vertex, 0);
  EXPECT_EQ(g::DefaultKnowledge().categories[p.category].id, "table");
  EXPECT_TRUE(p.on);
  EXPECT_EQ(p.gap_m, 0.0);
}

TEST(EventsGraphPlacement, BesideTheNearestPieceInTheListenersWords) {
  const Scene s = TableAndSofa();
  const GraphPlacement left = PlaceInGraph(s.graph, g::DefaultKnowledge(), s.set.ranked.front(), s.viewpoint, 3.0, {2.8, 0.8, 0.0});
  EXPECT_EQ(left.vertex, 0);
  EXPECT_FALSE(left.on);
  EXPECT_NEAR(left.gap_m, 0.3, 1e-12);
  EXPECT_EQ(left.word, g::Relation::kLeftOf);
  EXPECT_EQ(left.frame, g::Frame::kRelative);  // a table has no front: the relative frame
  const GraphPlacement behind = PlaceInGraph(s.graph, g::DefaultKnowledge(), s.set.ranked.front(), s.viewpoint, 3.0, {5.0, 0.0, 0.0});
  EXPECT_EQ(behind.vertex, 1);
  EXPECT_EQ(behind.word, g::Relation::kBehind);
}

}  // namespace
}  // namespace anchordb::engine
