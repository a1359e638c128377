#include "engine/octomap/leaf_centres.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "schema/error.h"

namespace anchordb::engine {

std::vector<Eigen::Vector3f> LeafCentres(const std::vector<Voxel>& voxels, double resolution_m, std::size_t max_points) {
  std::vector<Eigen::Vector3f> points_map;
  for (const Voxel& v : voxels) {
    const int n = std::max(1, static_cast<int>(std::lround(v.size_m / resolution_m)));  // leaves along each axis
    if (points_map.size() + static_cast<std::size_t>(n) * n * n > max_points) {
      throw Error(ErrorCode::kPayloadTooLarge,
                  "the OctoMap holds more occupied space than " + std::to_string(max_points) + " voxels", "octomap");
    }
    const Eigen::Vector3d corner_map = v.center_map - Eigen::Vector3d::Constant(0.5 * v.size_m);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        for (int k = 0; k < n; ++k) points_map.push_back((corner_map + resolution_m * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5)).cast<float>());
      }
    }
  }
  return points_map;
}

}  // namespace anchordb::engine
