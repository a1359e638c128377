#pragma once
// The words of the event layer (SPEC §4.4): each change event explains itself in a sentence, and the where-is
// answer is a sentence a robot can speak. Positions are in the map frame [m], printed with two decimals.
#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "engine/events/change_set.h"

namespace anchordb::engine {

// v with `digits` decimals ("0.45").
std::string FixedDigits(double v, int digits = 2);
// "(x, y, z)" with two decimals each.
std::string PositionText(const Eigen::Vector3d& p_m);

// Explanations of change events.
std::string AddedExplanation(Detection detection);  // meanwhile: while the robot was away; else while observing
std::string RemovedObservedExplanation();
std::string SeenThroughExplanation(int seen_through, int judged, const Eigen::Vector3d& last_seen_m);
std::string MoveExplanation(const std::string& label, std::int64_t instance_id, const Eigen::Vector3d& from_m,
                            const Eigen::Vector3d& to_m, double size_similarity);
std::string ReanalysisAddedExplanation(std::int64_t keyframe_id, std::int64_t background_scene_id);
std::string ReanalysisRemovedExplanation(std::int64_t background_scene_id);
std::string LabelledExplanation(bool from_operator);
// A classifier's class became the label of an object nobody named.
std::string ClassifiedExplanation(const std::string& classifier);

// English agreement by the label's last letter ("keys are", "the mug is"): good enough for spoken answers.
bool IsPluralLabel(const std::string& label);
// "at (x, y) in the map": where an object stands when no furniture places it.
std::string MapPositionPhrase(const Eigen::Vector3d& p_m);
// The where-is sentence: `where` is a phrase such as "on the table"; `present`: the object is (was, for a past time)
// there, else it was last seen there and taken away; `past`: the question asked about a past time.
std::string WhereSentence(const std::string& label, const std::string& where, bool present, bool past);

}  // namespace anchordb::engine
