#pragma once
// The decision rules of the event layer (thesis 3.3.4, 3.5.2; SPEC §4.4) on typed inputs: which known instance a
// segment is, when a view proves an object gone, and the lost-key rule that turns a removal and a later addition
// into a move.
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/events/change_set.h"
#include "engine/events/changes.h"

namespace anchordb::engine {

// Defaults of the thresholds (the service's settings start from these).
inline constexpr double kMoveMinSizeSimilarity = 0.45;   // lost-key rule: a less similar addition is another object
inline constexpr double kRemovedMinSeenThrough = 0.6;    // fraction of an instance's judged points seen through
inline constexpr int kRemovedMinVisiblePoints = 20;      // fewer judged points prove nothing

struct EventRules {
  MatchParams match;
  double move_min_size_similarity = kMoveMinSizeSimilarity;
  double removed_min_seen_through = kRemovedMinSeenThrough;
  int removed_min_visible_points = kRemovedMinVisiblePoints;
};

// Index of the instance the segment is (the nearest centroid among those that Matches() accepts and that are not
// `taken`), or -1. `taken` has one flag per instance.
int BestMatch(const Segment& s, const std::vector<KnownInstance>& instances, const std::vector<bool>& taken,
              const MatchParams& p);

// What a view says about an object believed present, from the visibility of its sample points.
enum class SeenThrough {
  kRemoved,     // enough points judged and most of them seen through: the object is gone
  kSeenAgain,   // not gone, and enough points confirmed: it was seen now
  kUndecided,   // too little evidence either way
};
SeenThrough JudgeSeenThrough(const Visibility& v, double min_seen_through, int min_visible_points);

// The lost-key rule (3.3.4): an addition seen being made continues the removal of a labelled object that has not been
// seen since (its newest history row is an absence at or before `stamp_ns`), when the sizes are compatible
// (SizeSimilarity >= min_size_similarity; the most similar wins, the later in the list among equals). Operator-locked
// and unlabelled instances never continue. Only observed additions count (an object that appeared while nobody
// watched is not taken for it): the caller asks only for those.
struct MoveMatch {
  int index = -1;            // into the instances
  double size_similarity = 0.0;
};
std::optional<MoveMatch> LostKeyMove(const Eigen::Vector3d& added_extent_m, const std::vector<KnownInstance>& instances,
                                     std::int64_t stamp_ns, double min_size_similarity);

// Re-analysis of an old keyframe (3.3.4) applies the background of a newer model of the same place: a model whose
// camera stands within `kReanalysisRadiusM` of the keyframe's, opened after the keyframe's own model, that took
// frames and was not forgotten. `candidates` come nearest first; the first that qualifies is chosen.
inline constexpr double kReanalysisRadiusM = 0.5;
inline constexpr int kReanalysisCandidates = 20;  // nearest models examined
struct ReanalysisCandidate {
  std::int64_t scene_id = 0;
  std::int64_t frames = 0;
  bool forgotten = false;
};
std::optional<std::int64_t> ChooseReanalysisModel(std::int64_t keyframe_scene_id,
                                                  const std::vector<ReanalysisCandidate>& candidates);

}  // namespace anchordb::engine
