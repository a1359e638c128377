#pragma once
// Pixel-wise evaluation of movable layers (thesis 3.5.1, Table 3.1): every pixel is TP, FP, FN or TN against a
// ground-truth mask, except those in the transition zone around the ground truth's boundary, which are ignored.
#include <cstdint>
#include <vector>

namespace anchordb::testing {

struct PixelCounts {
  std::int64_t tp = 0, fp = 0, fn = 0, tn = 0, ignored = 0;
  double Precision() const { return tp + fp ? static_cast<double>(tp) / (tp + fp) : 1.0; }
  double Recall() const { return tp + fn ? static_cast<double>(tp) / (tp + fn) : 1.0; }
  double F1() const { return 2 * tp + fp + fn ? 2.0 * tp / (2.0 * tp + fp + fn) : 1.0; }
  double Fpr() const { return fp + tn ? static_cast<double>(fp) / (fp + tn) : 0.0; }
  PixelCounts& operator+=(const PixelCounts& o) {
    tp += o.tp, fp += o.fp, fn += o.fn, tn += o.tn, ignored += o.ignored;
    return *this;
  }
};

// The band of pixels within `radius_px` of the ground truth's boundary (inside or outside), as 0/1.
std::vector<std::uint8_t> TransitionZone(const std::vector<std::uint8_t>& truth, int width, int height, int radius_px);

// `zone` may be empty (nothing ignored).
PixelCounts CountPixels(const std::vector<std::uint8_t>& movable, const std::vector<std::uint8_t>& truth,
                        const std::vector<std::uint8_t>& zone);

}  // namespace anchordb::testing
