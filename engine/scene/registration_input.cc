// The clouds registration.h aligns, from depth layers: back-projected without the pixels at depth discontinuities.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/scene/projection.h"
#include "engine/scene/registration.h"
#include "engine/scene/scene_model.h"

namespace anchordb::engine {

std::vector<Eigen::Vector3f> RegistrationCloud(std::span<const float> depth_m, const PinholeIntrinsics& K,
                                               const Eigen::Isometry3d& X_FrameCamera, double edge_jump_fraction) {
  if (!(edge_jump_fraction > 0.0)) return BackProject(depth_m, K, X_FrameCamera);
  // DepthEdgeMask works on integer depth: millimetres (0 = none) are fine enough for a jump of a few percent.
  std::vector<std::uint16_t> depth_mm(depth_m.size());
  for (std::size_t i = 0; i < depth_m.size(); ++i) {
    const float d = depth_m[i];
    depth_mm[i] = d > 0.0f && std::isfinite(d) ? static_cast<std::uint16_t>(std::clamp(std::lround(d * 1000.0f), 1L, 65535L)) : 0;
  }
  std::vector<std::uint8_t> keep = DepthEdgeMask(depth_mm, K.width, K.height, edge_jump_fraction);
  for (auto& k : keep) k = !k;
  return BackProject(depth_m, K, X_FrameCamera, keep);
}

}  // namespace anchordb::engine
