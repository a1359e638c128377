// The shape model's verification mode for the segmentation service, in a translation unit of its own:
// engine/shapes/shape_model.h declares engine::Detection, a name the event layer's headers use for an enum.
#include "engine/shapes/shape_model.h"

#include <string>
#include <utility>
#include <vector>

namespace anchordb::services {

std::vector<std::pair<std::string, double>> VerifySegment(const engine::ShapeModel& model, const std::vector<Eigen::Vector3f>& points_m) {
  std::vector<std::pair<std::string, double>> out;
  for (const engine::CategoryScore& s : engine::Verify(model, points_m).scores) out.emplace_back(s.category, s.probability);
  return out;
}

}  // namespace anchordb::services
