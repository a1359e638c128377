#pragma once
// A synthetic depth scene for keyframe-analysis tests: a 160x120 camera (fx = fy = 130 px) facing a wall 2 m away,
// with a 40x40 px box at 1.5 m in front of it when `box`. Depths in mm (raw frames at 1000 units per metre).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "services/scene/scene_types.h"

namespace anchordb::testing {

constexpr int kWallW = 160, kWallH = 120;

inline std::vector<std::uint16_t> WallDepthMm(bool box) {
  std::vector<std::uint16_t> d(kWallW * kWallH, 2000);
  if (box) for (int v = 40; v < 80; ++v) for (int u = 60; u < 100; ++u) d[v * kWallW + u] = 1500;
  return d;
}

// The camera of these frames.
inline PinholeIntrinsics WallCamera() { return {kWallW, kWallH, 130.0, 130.0, 79.5, 59.5}; }

// A raw frame of `depth` (which must outlive it) at `stamp_ns`.
inline services::FrameInput RawFrame(const std::vector<std::uint16_t>& depth, std::int64_t stamp_ns, bool wait_for_analysis = false) {
  services::FrameInput in;
  in.body = std::string_view(reinterpret_cast<const char*>(depth.data()), depth.size() * 2);
  in.png = false;
  in.stamp_ns = stamp_ns;
  in.wait_for_analysis = wait_for_analysis;
  return in;
}

}  // namespace anchordb::testing
