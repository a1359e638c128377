#pragma once
// Pictures of layers for people (PNG, north up: image row 0 is the top of the map).
#include <string>

#include "engine/grid/grid.h"
#include "engine/grid/map_server.h"

namespace anchordb::engine {

// Probability as map_server grey: p = 1 -> black (0), p = 0 -> white (255); round((1 - p) * 255).
GreyImage ProbabilityToImage(const ProbabilityGrid& probability);
// Occupancy values as map_server trinary grey (0 occupied, 254 free, 205 unknown).
GreyImage OccupancyToImage(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds);
// Label ids as colours (0 = white); a fixed palette so the same id always has the same colour.
std::string RenderLabelsPng(const LabelGrid& labels);

}  // namespace anchordb::engine
