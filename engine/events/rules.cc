#include "engine/events/rules.h"

#include <limits>

namespace anchordb::engine {

int BestMatch(const Segment& s, const std::vector<KnownInstance>& instances, const std::vector<bool>& taken,
              const MatchParams& p) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (taken[i]) continue;
    const Eigen::Vector3d& c = instances[i].position_m;
    const Eigen::Vector3d& e = instances[i].extent_m;
    if (!Matches(s, c, e, p)) continue;
    const double d = MatchDistance(s, c, e);
    if (d < best_d) best_d = d, best = static_cast<int>(i);
  }
  return best;
}

SeenThrough JudgeSeenThrough(const Visibility& v, double min_seen_through, int min_visible_points) {
  const int judged = v.confirmed + v.seen_through;
  if (judged < min_visible_points || v.seen_through < min_seen_through * judged) {
    return v.confirmed >= min_visible_points ? SeenThrough::kSeenAgain : SeenThrough::kUndecided;
  }
  return SeenThrough::kRemoved;
}

std::optional<MoveMatch> LostKeyMove(const Eigen::Vector3d& added_extent_m, const std::vector<KnownInstance>& instances,
                                     std::int64_t stamp_ns, double min_size_similarity) {
  std::optional<MoveMatch> out;
  double best_similarity = min_size_similarity;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const KnownInstance& r = instances[i];
    if (r.present || r.status_locked || r.labels.empty()) continue;
    if (!r.last_history || r.last_history->present || r.last_history->stamp_ns > stamp_ns) continue;
    const double similarity = SizeSimilarity(r.extent_m, added_extent_m);
    if (similarity >= best_similarity) best_similarity = similarity, out = MoveMatch{static_cast<int>(i), similarity};
  }
  return out;
}

std::optional<std::int64_t> ChooseReanalysisModel(std::int64_t keyframe_scene_id,
                                                  const std::vector<ReanalysisCandidate>& candidates) {
  for (const auto& c : candidates) {
    if (c.scene_id > keyframe_scene_id && c.frames > 0 && !c.forgotten) return c.scene_id;
  }
  return std::nullopt;
}

}  // namespace anchordb::engine
