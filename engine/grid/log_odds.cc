#include "engine/grid/log_odds.h"

#include <cmath>

namespace anchordb::engine {

float ProbabilityToLogOdds(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }

double LogOddsToProbability(float l) { return 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(l))); }

LogOddsModel::LogOddsModel(const LogOddsParams& p)
    : hit(ProbabilityToLogOdds(p.hit_probability)),
      miss(ProbabilityToLogOdds(p.miss_probability)),
      min(ProbabilityToLogOdds(p.clamp_min_probability)),
      max(ProbabilityToLogOdds(p.clamp_max_probability)) {}

ProbabilityGrid ToProbability(const LogOddsGrid& log_odds) {
  ProbabilityGrid out(log_odds.geometry, 0.5f);
  for (std::size_t i = 0; i < log_odds.cells.size(); ++i) {
    out.cells[i] = static_cast<float>(LogOddsToProbability(log_odds.cells[i]));
  }
  return out;
}

}  // namespace anchordb::engine
