#pragma once
// Where a thing stands relative to the furniture of a map's furniture graph, in words (SPEC §4.4): the answer of
// FurnitureService::Place, used by the where-is query of the events service.
#include <cstdint>
#include <optional>
#include <string>

namespace anchordb::services {

struct Placement {
  std::int64_t graph = 0;            // the furniture graph used
  std::string furniture;             // id of the nearest piece (a vertex of the graph)
  std::string category;              // its label under the best hypothesis (category id)
  std::string name;                  // what the robot calls it ("table")
  std::string relation;              // "on", or the relation id ("left_of", ...) as the listener would say it
  std::optional<std::string> frame;  // the frame that word is meant in ("relative" / "intrinsic"); none when "on"
  double gap_m = 0.0;                // distance from the piece's footprint [m] (0 when on)
  std::string phrase;                // "on the table", "to the left of the sofa"
};

}  // namespace anchordb::services
