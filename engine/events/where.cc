#include "engine/events/where.h"

#include <cmath>

namespace anchordb::engine {

int ChooseWhereCandidate(const std::vector<WhereCandidate>& candidates) {
  int best = -1;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const WhereCandidate& c = candidates[i];
    if (c.label_probability <= 0.0 || !c.stamp_ns) continue;
    if (best < 0) {
      best = static_cast<int>(i);
      continue;
    }
    const WhereCandidate& b = candidates[static_cast<std::size_t>(best)];
    if (c.label_probability > b.label_probability + 1e-9 ||
        (std::abs(c.label_probability - b.label_probability) <= 1e-9 && *c.stamp_ns > *b.stamp_ns)) {
      best = static_cast<int>(i);
    }
  }
  return best;
}

std::string HowKnown(const std::optional<PositionOrigin>& origin) {
  if (!origin) return "observed";
  return origin->event_type == "moved" ? "inferred" : origin->detection;
}

double PositionConfidence(std::string_view how) {
  return how == "observed" ? 0.95 : how == "meanwhile" ? 0.85 : how == "inferred" ? 0.7 : 0.8;
}

double WhereConfidence(double label_probability, std::string_view how) { return label_probability * PositionConfidence(how); }

PlacementWords DescribePlacement(const Placement& placed, const std::string& piece_name) {
  if (placed.on) return {"on", "on the " + piece_name};
  return {grounding::RelationId(placed.relative), std::string(grounding::RelationPhrase(placed.relative)) + " the " + piece_name};
}

}  // namespace anchordb::engine
