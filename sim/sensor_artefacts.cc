#include "sim/sensor_artefacts.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace anchordb::sim::detail {
namespace {

constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

std::uint64_t SplitMix64(std::uint64_t x) {
  x += kGolden;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Independent random streams derived from the frame's seed.
enum class Stream : std::uint64_t { kCorrelatedNoise = 1, kJitterU, kJitterV, kDropout, kEdgeChoice, kEdgeMix };

std::uint64_t StreamSeed(std::uint64_t seed, Stream stream) {
  return SplitMix64(seed ^ SplitMix64(static_cast<std::uint64_t>(stream) * 0xD1B54A32D192ED03ull));
}

// The index-th uniform of a stream, in [0, 1).
double HashUniform(std::uint64_t stream_seed, std::uint64_t index) {
  return static_cast<double>(SplitMix64(stream_seed + index * kGolden) >> 11) * (1.0 / 9007199254740992.0);
}

// The (2 pair)-th and (2 pair + 1)-th standard normals of a stream (Box-Muller on two hashed uniforms).
void HashNormalPair(std::uint64_t stream_seed, std::uint64_t pair, float& first, float& second) {
  const double u1 = 1.0 - HashUniform(stream_seed, 2 * pair);  // (0, 1]
  const double u2 = HashUniform(stream_seed, 2 * pair + 1);
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double angle = 6.283185307179586 * u2;
  first = static_cast<float>(r * std::cos(angle));
  second = static_cast<float>(r * std::sin(angle));
}

// round(x) for |x| < 2^31, without a libm call.
inline int RoundToInt(double x) {
  const double y = x + 0.5;
  const int t = static_cast<int>(y);
  return t - (y < t ? 1 : 0);
}

// round(x) for 0 <= x < 2^62, without a libm call.
inline double RoundNonNegative(double x) { return static_cast<double>(static_cast<std::int64_t>(x + 0.5)); }

// A Gaussian field of unit variance at every pixel, correlated over about `spacing_px`: i.i.d. standard normals on
// a grid of that spacing, bilinearly interpolated, and divided by the standard deviation the interpolation leaves
// at that offset (sqrt of the sum of the squared weights), so the field's statistics do not depend on the offset.
void SmoothField(std::uint64_t stream_seed, int width, int height, double spacing_px, std::vector<float>& field) {
  const int grid_w = static_cast<int>(std::floor((width - 1) / spacing_px)) + 2;
  const int grid_h = static_cast<int>(std::floor((height - 1) / spacing_px)) + 2;
  std::vector<float> grid(static_cast<std::size_t>(grid_w) * grid_h + 1);
  for (std::size_t k = 0; k + 1 < grid.size(); k += 2) HashNormalPair(stream_seed, k / 2, grid[k], grid[k + 1]);
  std::vector<int> col(static_cast<std::size_t>(width));
  std::vector<float> col_a(static_cast<std::size_t>(width)), col_inv_sd(static_cast<std::size_t>(width));
  for (int u = 0; u < width; ++u) {
    const double g = u / spacing_px;
    const double a = g - std::floor(g);
    col[static_cast<std::size_t>(u)] = static_cast<int>(std::floor(g));
    col_a[static_cast<std::size_t>(u)] = static_cast<float>(a);
    col_inv_sd[static_cast<std::size_t>(u)] = static_cast<float>(1.0 / std::sqrt((1.0 - a) * (1.0 - a) + a * a));
  }
  field.resize(static_cast<std::size_t>(width) * height);
  for (int v = 0; v < height; ++v) {
    const double g = v / spacing_px;
    const int row = static_cast<int>(std::floor(g));
    const float b = static_cast<float>(g - row);
    const float row_inv_sd = 1.0f / std::sqrt((1.0f - b) * (1.0f - b) + b * b);
    const float* g0 = grid.data() + static_cast<std::size_t>(row) * grid_w;
    const float* g1 = g0 + grid_w;
    float* out = field.data() + static_cast<std::size_t>(v) * width;
    for (int u = 0; u < width; ++u) {
      const int c = col[static_cast<std::size_t>(u)];
      const float a = col_a[static_cast<std::size_t>(u)];
      const float top = (1.0f - a) * g0[c] + a * g0[c + 1];
      const float bottom = (1.0f - a) * g1[c] + a * g1[c + 1];
      out[u] = ((1.0f - b) * top + b * bottom) * (col_inv_sd[static_cast<std::size_t>(u)] * row_inv_sd);
    }
  }
}

// x with P(N(0, 1) > x) = upper_tail, by bisection on erfc (once per frame).
double NormalUpperQuantile(double upper_tail) {
  double lo = -10.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > upper_tail ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Per pixel the largest and the smallest disparity [px] of the measurable pixels in its (2 band + 1)^2
// neighbourhood (separable: rows, then columns); a pixel with no measurable neighbour gets max < min.
void NeighbourhoodDisparityRange(const std::vector<double>& ideal_m, int width, int height, int band, double fb_px_m,
                                 std::vector<float>& max_px, std::vector<float>& min_px) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  // Scratch reused by every frame of the thread: no page faults for fresh buffers.
  thread_local std::vector<float> disparity, row_max, row_min;
  disparity.resize(n);
  row_max.resize(n);
  row_min.resize(n);
  for (std::size_t i = 0; i < n; ++i) disparity[i] = ideal_m[i] > 0.0 ? static_cast<float>(fb_px_m / ideal_m[i]) : 0.0f;
  constexpr float kNone = 1e30f;
  for (int v = 0; v < height; ++v) {
    const float* d = disparity.data() + static_cast<std::size_t>(v) * width;
    for (int u = 0; u < width; ++u) {
      float hi = 0.0f, lo = kNone;
      for (int x = std::max(0, u - band); x <= std::min(width - 1, u + band); ++x) {
        if (d[x] <= 0.0f) continue;
        hi = std::max(hi, d[x]);
        lo = std::min(lo, d[x]);
      }
      row_max[static_cast<std::size_t>(v) * width + u] = hi;
      row_min[static_cast<std::size_t>(v) * width + u] = lo;
    }
  }
  max_px.assign(n, 0.0f);
  min_px.assign(n, kNone);
  for (int v = 0; v < height; ++v) {
    for (int y = std::max(0, v - band); y <= std::min(height - 1, v + band); ++y) {
      const float* hi = row_max.data() + static_cast<std::size_t>(y) * width;
      const float* lo = row_min.data() + static_cast<std::size_t>(y) * width;
      float* out_hi = max_px.data() + static_cast<std::size_t>(v) * width;
      float* out_lo = min_px.data() + static_cast<std::size_t>(v) * width;
      for (int u = 0; u < width; ++u) {
        out_hi[u] = std::max(out_hi[u], hi[u]);
        out_lo[u] = std::min(out_lo[u], lo[u]);
      }
    }
  }
}

void Require(bool ok, const char* field, const char* range) {
  if (!ok) throw std::invalid_argument(std::string("Render: sensor.") + field + " must be " + range);
}

}  // namespace

void CheckSensorModel(const SensorModel& s) {
  const auto fraction = [](double x) { return x >= 0.0 && x <= 1.0; };
  Require(fraction(s.correlated_noise_fraction), "correlated_noise_fraction", "in [0, 1]");
  Require(s.correlated_noise_spacing_px >= 1.0 && s.correlated_noise_spacing_px <= 64.0, "correlated_noise_spacing_px",
          "in [1, 64]");
  Require(s.disparity_focal_px > 0.0 && std::isfinite(s.disparity_focal_px), "disparity_focal_px", "positive");
  Require(s.disparity_step_px > 0.0 && std::isfinite(s.disparity_step_px), "disparity_step_px", "positive");
  Require(!s.quantise_disparity || s.projector_baseline_m > 0.0, "projector_baseline_m",
          "positive when quantise_disparity is on");
  Require(s.lateral_sigma_px >= 0.0 && s.lateral_sigma_px <= 10.0, "lateral_sigma_px", "in [0, 10]");
  Require(s.flying_band_px >= 1 && s.flying_band_px <= 5, "flying_band_px", "in [1, 5]");
  Require(s.flying_min_jump_px >= 0.0 && std::isfinite(s.flying_min_jump_px), "flying_min_jump_px", ">= 0");
  Require(fraction(s.flying_fraction) && fraction(s.edge_dropout_fraction) &&
              s.flying_fraction + s.edge_dropout_fraction <= 1.0,
          "flying_fraction and edge_dropout_fraction", "in [0, 1] with a sum <= 1");
  Require(s.dropout_fraction >= 0.0 && s.dropout_fraction < 1.0, "dropout_fraction", "in [0, 1)");
  Require(s.dropout_spacing_px >= 1.0 && s.dropout_spacing_px <= 64.0, "dropout_spacing_px", "in [1, 64]");
}

void MeasureDepth(const SensorModel& sensor, int width, int height, std::uint64_t seed,
                  const std::vector<double>& ideal_m, const std::vector<double>& white_normal,
                  std::vector<std::uint16_t>& depth_mm) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  depth_mm.assign(n, 0);
  const bool noisy = sensor.noise;
  const bool axial = noisy && sensor.axial_noise;
  const bool correlated = axial && sensor.correlated_noise_fraction > 0.0;
  const bool jitter = noisy && sensor.lateral_jitter && sensor.lateral_sigma_px > 0.0;
  const bool flying = noisy && sensor.flying_pixels;
  const bool quantise = noisy && sensor.quantise_disparity;
  const bool dropouts = noisy && sensor.speckle_dropouts && sensor.dropout_fraction > 0.0;
  const double spacing = sensor.correlated_noise_spacing_px;
  // Scratch reused by every frame of the thread: no page faults for fresh buffers.
  thread_local std::vector<float> correlated_noise, jitter_u, jitter_v, dropout_field;
  if (correlated) SmoothField(StreamSeed(seed, Stream::kCorrelatedNoise), width, height, spacing, correlated_noise);
  if (jitter) {
    SmoothField(StreamSeed(seed, Stream::kJitterU), width, height, spacing, jitter_u);
    SmoothField(StreamSeed(seed, Stream::kJitterV), width, height, spacing, jitter_v);
  }
  if (dropouts) SmoothField(StreamSeed(seed, Stream::kDropout), width, height, sensor.dropout_spacing_px, dropout_field);
  const float dropout_threshold = dropouts ? static_cast<float>(NormalUpperQuantile(sensor.dropout_fraction)) : 0.0f;
  const double w_correlated = std::sqrt(sensor.correlated_noise_fraction);
  const double w_white = std::sqrt(1.0 - sensor.correlated_noise_fraction);
  const double fb_px_m = sensor.disparity_focal_px * sensor.projector_baseline_m;
  const double step_px = sensor.disparity_step_px;
  const std::uint64_t edge_choice_seed = StreamSeed(seed, Stream::kEdgeChoice);
  const std::uint64_t edge_mix_seed = StreamSeed(seed, Stream::kEdgeMix);
  thread_local std::vector<float> disparity_max_px, disparity_min_px;
  if (flying) {
    NeighbourhoodDisparityRange(ideal_m, width, height, sensor.flying_band_px, fb_px_m, disparity_max_px,
                                disparity_min_px);
  }

  // Raw pointers: thread_local vectors would be looked up again at every access.
  const float* const noise_c = correlated_noise.data();
  const float* const shift_u = jitter_u.data();
  const float* const shift_v = jitter_v.data();
  const float* const drop = dropout_field.data();
  const float* const d_max = disparity_max_px.data();
  const float* const d_min = disparity_min_px.data();
  const double* const ideal = ideal_m.data();
  const double* const white = white_normal.data();
  std::uint16_t* const out = depth_mm.data();
  const double fb_over_step = fb_px_m / step_px;
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      if (dropouts && drop[i] > dropout_threshold) continue;
      // Lateral noise: the pixel reports what a pixel a (rounded, correlated) offset away sees.
      int su = u, sv = v;
      if (jitter) {
        su = std::clamp(u + RoundToInt(sensor.lateral_sigma_px * shift_u[i]), 0, width - 1);
        sv = std::clamp(v + RoundToInt(sensor.lateral_sigma_px * shift_v[i]), 0, height - 1);
      }
      const std::size_t source = static_cast<std::size_t>(sv) * width + su;
      double z_m = ideal[source];
      if (z_m <= 0.0) continue;
      // The correlation window straddles a depth discontinuity: the match lands on either side or in between.
      if (flying && d_max[source] - d_min[source] > sensor.flying_min_jump_px) {
        const double choice = HashUniform(edge_choice_seed, i);
        if (choice < sensor.flying_fraction) {
          const double z_near = fb_px_m / d_max[source], z_far = fb_px_m / d_min[source];
          z_m = z_near + HashUniform(edge_mix_seed, i) * (z_far - z_near);
        } else if (choice < sensor.flying_fraction + sensor.edge_dropout_fraction) {
          continue;
        }
      }
      double measured_m = z_m;
      if (axial) {
        double sigma_m = NguyenSigmaM(z_m);
        if (quantise) {
          // Nguyen's sigma was fitted to real, already quantised depth: the rounding's own variance step^2 / 12
          // comes out of the Gaussian part.
          const double step_m = z_m * z_m * step_px / fb_px_m;
          sigma_m = std::sqrt(std::max(sigma_m * sigma_m - step_m * step_m / 12.0, 0.0));
        }
        const double normal =
            correlated ? w_correlated * noise_c[i] + w_white * white[i] : white[i];
        measured_m += sigma_m * normal;
      }
      if (quantise && measured_m > 0.0) {
        const double disparity_steps = RoundNonNegative(fb_over_step / measured_m);
        measured_m = disparity_steps >= 1.0 ? fb_px_m / (disparity_steps * step_px) : 65.535;
      }
      const double mm = std::clamp(measured_m * 1000.0, 1.0, 65535.0);
      out[i] = static_cast<std::uint16_t>(RoundNonNegative(mm));
    }
  }
}

}  // namespace anchordb::sim::detail
