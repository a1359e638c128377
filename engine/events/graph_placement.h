#pragma once
// Where a thing stands relative to the furniture of a furniture graph, in the words the graph's listener prefers
// (SPEC §4.4, thesis 5.3.5): the nearest piece (engine/events/placement.h), "on" it when inside its footprint,
// otherwise the relation seen from the graph's viewpoint spoken in the frame the listener most likely uses
// (grounding::PreferredWord under the best hypothesis).
#include <Eigen/Core>

#include "engine/grounding/grounding.h"

namespace anchordb::engine {

struct GraphPlacement {
  int vertex = -1;    // index of the nearest piece in graph.vertices
  int category = 0;   // its label under `best` (index into the knowledge's categories)
  bool on = false;    // inside its footprint
  grounding::Relation word = grounding::Relation::kLeftOf;  // when not on: the word to say
  grounding::Frame frame = grounding::Frame::kRelative;     // and the frame it is meant in
  double gap_m = 0.0;  // distance from the piece's footprint [m] (0 when on)
};

// p_map: the thing's position in the map frame [m] (z ignored). relation_sharpness: kappa of the graph
// (grounding::RelationFromOffset). The graph has at least one vertex.
GraphPlacement PlaceInGraph(const grounding::FurnitureGraph& graph, const grounding::Knowledge& knowledge,
                            const grounding::Hypothesis& best, const grounding::Viewpoint& viewpoint,
                            double relation_sharpness, const Eigen::Vector3d& p_map);

}  // namespace anchordb::engine
