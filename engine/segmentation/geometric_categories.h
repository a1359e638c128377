#pragma once
// A category distribution p(f) for a furniture segment from its gross shape alone: height, footprint size and the
// share of its points on its top surface, scored against one prototype per category (a Gaussian per measure, the
// product normalised). It is the fallback when no 3D shape model (engine/shapes, thesis 4.1) is given, and the prior
// the shape model's distribution is combined with: it knows that a table is about 0.75 m high with most of what the
// robot sees of it on top, that a sofa's densest layer is its seat, half its height, and that a shelf is tall and
// shallow — not more. Prototype figures: typical furniture
// sizes (a dining table 0.72-0.76 m, a sofa seat 0.40-0.45 m with a back of 0.8-0.9 m, ...), chosen broad.
#include <optional>
#include <string>
#include <vector>

#include "engine/segmentation/furniture_segmentation.h"

namespace anchordb::engine::segmentation {

struct ShapeMeasures {
  double height_m = 0.0;       // top above the floor (or above the segment's own bottom without a floor) [m]
  double major_m = 0.0;        // footprint's longer side [m]
  double minor_m = 0.0;        // footprint's shorter side [m]
  double top_fraction = 0.0;   // share of the points in the densest horizontal layer (5 cm) above 0.25 m
  double layer_ratio = 1.0;    // that layer's height over height_m: ~1 for a table top, ~0.5 for a seat
};

// `floor_z_m`: the floor's height when the segmentation found it.
ShapeMeasures MeasureSegment(const FurnitureSegment& segment, std::optional<double> floor_z_m);

// p(f) over `category_ids` (ids of the grounding knowledge table, engine/grounding/categories.json); an id without a
// prototype gets the smallest score of the others. Sums to 1; uniform when `category_ids` has no known id.
std::vector<double> GeometricCategories(const ShapeMeasures& m, const std::vector<std::string>& category_ids);

}  // namespace anchordb::engine::segmentation
