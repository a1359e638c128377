#include "engine/scene/scene_model.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace anchordb::engine {

SceneModelState NewSceneModel(int width, int height) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  SceneModelState s;
  s.width = width;
  s.height = height;
  s.background_m.assign(n, 0.0f);
  s.weight.assign(n, 1.0f);
  s.movable.assign(n, 0);
  s.dynamic.assign(n, 0);
  return s;
}

namespace {

// Whether depths a and b (both > 0) differ by more than jump_fraction times the nearer one.
inline bool Jump(std::uint16_t a, std::uint16_t b, float jump_fraction) {
  const float lo = static_cast<float>(std::min(a, b)), hi = static_cast<float>(std::max(a, b));
  return hi - lo > jump_fraction * lo;
}

// Whether pixel (u, v), measured, has a measured 4-neighbour across a jump.
inline bool IsDepthEdge(const std::uint16_t* d, int u, int v, int width, int height, float jump_fraction) {
  const std::size_t i = static_cast<std::size_t>(v) * width + u;
  const std::uint16_t a = d[i];
  if (u > 0 && d[i - 1] != 0 && Jump(a, d[i - 1], jump_fraction)) return true;
  if (u + 1 < width && d[i + 1] != 0 && Jump(a, d[i + 1], jump_fraction)) return true;
  if (v > 0 && d[i - width] != 0 && Jump(a, d[i - width], jump_fraction)) return true;
  return v + 1 < height && d[i + width] != 0 && Jump(a, d[i + width], jump_fraction);
}

}  // namespace

std::vector<std::uint8_t> DepthEdgeMask(std::span<const std::uint16_t> depth, int width, int height,
                                        double jump_fraction) {
  std::vector<std::uint8_t> mask(depth.size(), 0);
  const float jump = static_cast<float>(jump_fraction);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      mask[i] = depth[i] != 0 && IsDepthEdge(depth.data(), u, v, width, height, jump);
    }
  }
  return mask;
}

FrameCounts ApplyFrame(SceneModelState& state, std::span<const std::uint16_t> depth, double units_per_m,
                       std::span<const std::uint8_t> dynamic_mask, const SceneModelParams& params) {
  FrameCounts counts;
  const std::size_t n = state.background_m.size();
  const bool has_mask = !dynamic_mask.empty();
  const bool exclude = params.dynamic_mode == DynamicMode::kExcludeFromInput;
  const float beta = static_cast<float>(params.beta);
  const float metres_per_unit = static_cast<float>(1.0 / units_per_m);
  float* s_bg = state.background_m.data();
  float* s_w = state.weight.data();
  std::uint8_t* s_mov = state.movable.data();
  std::uint8_t* s_dyn = state.dynamic.data();
  const int width = state.width, height = state.height;
  const bool drop_edges = params.drop_depth_edges && n == static_cast<std::size_t>(width) * height;
  // Row by row when filtering edges (pixel coordinates without a division), else one row of all n pixels.
  const int rows = drop_edges ? height : 1;
  const std::size_t row_length = drop_edges ? static_cast<std::size_t>(width) : n;
  for (int v = 0; v < rows; ++v) {
    for (std::size_t u = 0; u < row_length; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * row_length + u;
      const bool in_d = has_mask && dynamic_mask[i] != 0;
      if (in_d && exclude) {  // F'_t = F_t \ D_t
        s_mov[i] = 0;
        s_dyn[i] = 1;
        ++counts.dynamic;
        continue;
      }
      if (depth[i] == 0 || (drop_edges && IsDepthEdge(depth.data(), static_cast<int>(u), v, width, height, beta))) {
        ++counts.no_depth;
        continue;
      }
      const float f = depth[i] * metres_per_unit;
      const float s = s_bg[i];
      bool moved = false;
      if (std::abs(s - f) < beta * s) {
        s_bg[i] = s + (f - s) / s_w[i];
        s_w[i] += 1.0f;
        ++counts.supported;
      } else if (f > s) {
        s_bg[i] = f;
        s_w[i] = 1.0f;
        ++counts.reset;
      } else {
        moved = true;
      }
      // eqs. 3.4-3.5 (in exclude mode in_d is false here, so this is plain O_t).
      s_mov[i] = moved && !in_d;
      s_dyn[i] = moved && in_d;
      counts.movable += s_mov[i];
      counts.dynamic += s_dyn[i];
    }
  }
  ++state.frames;
  return counts;
}

std::vector<std::uint8_t> CleanMovable(const std::vector<std::uint8_t>& movable, int width, int height, int window,
                                       double min_fraction) {
  const cv::Mat m(height, width, CV_8U, const_cast<std::uint8_t*>(movable.data()));
  cv::Mat sum;
  cv::integral(m, sum, CV_32S);  // (height+1) x (width+1)
  const int r = window / 2;
  const int others = window * window - 1;
  std::vector<std::uint8_t> out(movable.size(), 0);
  for (int y = 0; y < height; ++y) {
    const int y0 = std::max(0, y - r), y1 = std::min(height, y + r + 1);
    const int* top = sum.ptr<int>(y0);
    const int* bottom = sum.ptr<int>(y1);
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      if (!movable[i]) continue;
      const int x0 = std::max(0, x - r), x1 = std::min(width, x + r + 1);
      const int count = bottom[x1] - bottom[x0] - top[x1] + top[x0] - 1;  // without the pixel itself
      out[i] = count >= min_fraction * others ? 1 : 0;
    }
  }
  return out;
}

}  // namespace anchordb::engine
