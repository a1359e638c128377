#include "engine/events/analysis_backlog.h"

namespace anchordb::engine {

bool RefusesFrames(const AnalysisBacklogLimits& limits, std::int64_t pending) {
  return limits.max_pending > 0 && pending >= limits.max_pending;
}

bool NeedsCatchUp(const AnalysisBacklogLimits& limits, std::int64_t pending) {
  return limits.catch_up_at > 0 && pending >= limits.catch_up_at;
}

}  // namespace anchordb::engine
