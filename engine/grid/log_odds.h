#pragma once
// Clamped log-odds arithmetic for probability layers (the OctoMap scheme: add log-odds of hit or miss,
// clamp to [log-odds(clamp_min), log-odds(clamp_max)]).
#include "engine/grid/grid.h"
#include "schema/types.h"

namespace anchordb::engine {

float ProbabilityToLogOdds(double probability);
double LogOddsToProbability(float log_odds);

struct LogOddsModel {
  explicit LogOddsModel(const LogOddsParams& params);
  float hit;
  float miss;
  float min;
  float max;
  float Raise(float l) const { return l + hit > max ? max : l + hit; }
  float Lower(float l) const { return l + miss < min ? min : l + miss; }
};

ProbabilityGrid ToProbability(const LogOddsGrid& log_odds);

}  // namespace anchordb::engine
