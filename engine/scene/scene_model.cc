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

// jump[k] = 1 where the measured pair (a[k], b[k]) differs by more than jump_fraction times its nearer depth:
// hi - lo > threshold[lo], threshold[d] = floor(jump_fraction * d) (65536 entries, and 0 -> never a jump).
void PairJumps(const std::uint16_t* __restrict a, const std::uint16_t* __restrict b, std::size_t count,
               const std::uint32_t* __restrict threshold, std::uint8_t* __restrict jump) {
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t lo = std::min(a[k], b[k]), hi = std::max(a[k], b[k]);
    jump[k] = static_cast<std::uint8_t>(hi - lo > threshold[lo]);
  }
}

// The thresholds of PairJumps for jump_fraction, cached per thread for the last fraction used.
const std::uint32_t* JumpThresholds(float jump_fraction) {
  thread_local std::vector<std::uint32_t> table;
  thread_local float table_fraction = -1.0f;
  if (table.empty() || table_fraction != jump_fraction) {
    table.resize(65536);
    table[0] = 0xFFFFFFFFu;  // no measurement: never a jump
    for (std::uint32_t d = 1; d < 65536; ++d) {
      table[d] = static_cast<std::uint32_t>(std::min(std::floor(static_cast<double>(jump_fraction) * d), 4e9));
    }
    table_fraction = jump_fraction;
  }
  return table.data();
}

// The depth-edge filter's byte-wise OR, vectorised by GCC through its optimize attribute (clang, which has no such
// attribute, gets the plain loop).
#if defined(__GNUC__) && !defined(__clang__)
#define ANCHORDB_VECTORIZE __attribute__((optimize("tree-vectorize")))
#else
#define ANCHORDB_VECTORIZE
#endif
ANCHORDB_VECTORIZE void OrInto(const std::uint8_t* __restrict from, std::size_t count, std::uint8_t* __restrict to) {
  for (std::size_t k = 0; k < count; ++k) to[k] |= from[k];
}

void FillDepthEdgeMask(std::span<const std::uint16_t> depth, int width, int height, float jump_fraction,
                       std::vector<std::uint8_t>& mask) {
  mask.assign(depth.size(), 0);
  const std::size_t w = static_cast<std::size_t>(width);
  thread_local std::vector<std::uint8_t> jump;  // one row of pair results, reused
  jump.resize(w);
  const std::uint32_t* threshold = JumpThresholds(jump_fraction);
  for (int v = 0; v < height; ++v) {
    const std::uint16_t* row = depth.data() + static_cast<std::size_t>(v) * w;
    std::uint8_t* m = mask.data() + static_cast<std::size_t>(v) * w;
    if (width > 1) {  // right neighbours: both pixels of the pair
      PairJumps(row, row + 1, w - 1, threshold, jump.data());
      OrInto(jump.data(), w - 1, m);
      OrInto(jump.data(), w - 1, m + 1);
    }
    if (v + 1 < height) {  // neighbours below
      PairJumps(row, row + w, w, threshold, jump.data());
      OrInto(jump.data(), w, m);
      OrInto(jump.data(), w, m + w);
    }
  }
}

}  // namespace

std::vector<std::uint8_t> DepthEdgeMask(std::span<const std::uint16_t> depth, int width, int height,
                                        double jump_fraction) {
  std::vector<std::uint8_t> mask;
  FillDepthEdgeMask(depth, width, height, static_cast<float>(jump_fraction), mask);
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
  const bool drop_edges = params.drop_depth_edges && n == static_cast<std::size_t>(state.width) * state.height;
  thread_local std::vector<std::uint8_t> edge;  // scratch reused by the thread's frames
  if (drop_edges) FillDepthEdgeMask(depth, state.width, state.height, beta, edge);
  const std::uint8_t* is_edge = drop_edges ? edge.data() : nullptr;
  {
    for (std::size_t i = 0; i < n; ++i) {
      const bool in_d = has_mask && dynamic_mask[i] != 0;
      if (in_d && exclude) {  // F'_t = F_t \ D_t
        s_mov[i] = 0;
        s_dyn[i] = 1;
        ++counts.dynamic;
        continue;
      }
      if (depth[i] == 0 || (is_edge && is_edge[i])) {
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
