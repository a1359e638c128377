#include "engine/events/sentences.h"

#include <sstream>

namespace anchordb::engine {

std::string FixedDigits(double v, int digits) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string PositionText(const Eigen::Vector3d& p) {
  return "(" + FixedDigits(p.x()) + ", " + FixedDigits(p.y()) + ", " + FixedDigits(p.z()) + ")";
}

std::string AddedExplanation(Detection detection) {
  return detection == Detection::kMeanwhile
             ? "an object stands in front of the background merged from the earlier visit and matches no "
               "object known to be there: added while the robot was away"
             : "an object stands in front of the background at the end of the action layer and did not at its "
               "start: added while observing";
}

std::string RemovedObservedExplanation() {
  return "an object stood in front of the background at the start of the action layer and the sensor sees "
         "through it at its end: removed while observing";
}

std::string SeenThroughExplanation(int seen_through, int judged, const Eigen::Vector3d& last_seen_m) {
  return "the view now sees through " + std::to_string(seen_through) + " of " + std::to_string(judged) +
         " measured points of the object last seen at " + PositionText(last_seen_m) + ": removed while the robot was away";
}

std::string MoveExplanation(const std::string& label, std::int64_t instance_id, const Eigen::Vector3d& from_m,
                            const Eigen::Vector3d& to_m, double size_similarity) {
  return "inferred move (lost-key rule, thesis 3.3.4): '" + label + "' (instance " + std::to_string(instance_id) +
         ") was removed from " + PositionText(from_m) + " and has not been seen since; this object was added at " +
         PositionText(to_m) + " by an observed action, without a new label, and is of compatible size (similarity " +
         FixedDigits(size_similarity) + ")";
}

std::string ReanalysisAddedExplanation(std::int64_t keyframe_id, std::int64_t background_scene_id) {
  return "keyframe " + std::to_string(keyframe_id) + " re-analysed with the background of scene " +
         std::to_string(background_scene_id) + ": an object stood here then that was part of the background at the time";
}

std::string ReanalysisRemovedExplanation(std::int64_t background_scene_id) {
  return "the background of scene " + std::to_string(background_scene_id) + " lies behind where this object stood: "
         "it is gone";
}

std::string LabelledExplanation(bool from_operator) {
  return from_operator ? "an operator set the label; automatic processing will not change it"
                       : "a person named the object in dialog";
}

std::string ClassifiedExplanation(const std::string& classifier) {
  return "classifier '" + classifier + "' named the object from its segment; a person's label would replace it";
}

bool IsPluralLabel(const std::string& label) { return !label.empty() && label.back() == 's'; }

std::string MapPositionPhrase(const Eigen::Vector3d& p) {
  return "at (" + std::to_string(p.x()).substr(0, 5) + ", " + std::to_string(p.y()).substr(0, 5) + ") in the map";
}

std::string WhereSentence(const std::string& label, const std::string& where, bool present, bool past) {
  const bool plural = IsPluralLabel(label);
  const std::string is = past ? (plural ? " were " : " was ") : (plural ? " are " : " is ");
  return present ? "The " + label + is + where + "."
                 : "The " + label + (plural ? " were" : " was") + " last seen " + where + "; " +
                       (plural ? "they were" : "it was") + " taken away and " + (plural ? "have" : "has") +
                       " not been seen since.";
}

}  // namespace anchordb::engine
