#include "engine/scene/projection.h"

namespace anchordb::engine {

std::vector<Eigen::Vector3f> BackProject(std::span<const float> depth_m, const PinholeIntrinsics& K,
                                         const Eigen::Isometry3d& X_MapCamera, std::span<const std::uint8_t> mask) {
  std::vector<Eigen::Vector3f> points;
  const Eigen::Matrix3f R = X_MapCamera.linear().cast<float>();
  const Eigen::Vector3f t = X_MapCamera.translation().cast<float>();
  const float inv_fx = static_cast<float>(1.0 / K.fx), inv_fy = static_cast<float>(1.0 / K.fy);
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * K.width + u;
      const float z = depth_m[i];
      if (z <= 0.0f || (!mask.empty() && !mask[i])) continue;
      const Eigen::Vector3f p_C((u - static_cast<float>(K.cx)) * inv_fx * z, (v - static_cast<float>(K.cy)) * inv_fy * z, z);
      points.push_back(R * p_C + t);
    }
  }
  return points;
}

std::vector<Eigen::Vector3f> BackProjectRaw(std::span<const std::uint16_t> depth, double units_per_m,
                                            const PinholeIntrinsics& K, const Eigen::Isometry3d& X_MapCamera) {
  std::vector<float> metres(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) metres[i] = static_cast<float>(depth[i] / units_per_m);
  return BackProject(metres, K, X_MapCamera);
}

Eigen::Isometry3d ToIsometry(const Pose3& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = pose.orientation.toRotationMatrix();
  X.translation() = pose.position_m;
  return X;
}

}  // namespace anchordb::engine
