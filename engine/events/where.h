#pragma once
// The where-is question (thesis 1.4, 3.3.4; SPEC §4.4): which instance a label means, how sure the answer is, and
// how the object stands relative to the nearest furniture when plain geometry places it.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/events/placement.h"

namespace anchordb::engine {

// An instance that carries the label: p(label) and the stamp of its history row at the asked time (nullopt: none).
struct WhereCandidate {
  double label_probability = 0.0;
  std::optional<std::int64_t> stamp_ns;
};
// The candidate the label most likely means (greatest p(label); within 1e-9 the more recent position), or -1 when no
// candidate has p > 0 and a position at that time.
int ChooseWhereCandidate(const std::vector<WhereCandidate>& candidates);

// How the position is known, from the event that put the instance there (type and detection): "inferred" for a
// move, else the event's detection (observed | meanwhile | reanalysis | dialog | operator); "observed" without one.
struct PositionOrigin {
  std::string event_type;
  std::string detection;
};
std::string HowKnown(const std::optional<PositionOrigin>& origin);
// How reliable a position known that way is: observed 0.95, meanwhile (merged from another visit) 0.85, inferred
// 0.7, anything else 0.8.
double PositionConfidence(std::string_view how);
// The answer's confidence: how sure the label is, times how the position is known.
double WhereConfidence(double label_probability, std::string_view how);

// The words of a plain-geometry placement against the piece it names: relation id ("on", "left_of", ...) and the
// phrase ("on the table", "to the left of the table").
struct PlacementWords {
  std::string relation;
  std::string phrase;
};
PlacementWords DescribePlacement(const Placement& placed, const std::string& piece_name);

}  // namespace anchordb::engine
