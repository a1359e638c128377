#include "engine/grid/visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/grid/observation.h"

namespace anchordb::engine {
namespace {

// Safety margin in pseudo-angle units. The pseudo-angle changes at most as fast as the angle, so a direction that
// is kMargin away from a square's silhouette corners misses every grid corner of the square by more than 1e-5 rad
// as seen from the sensor. The traversal's crossing parameters carry relative errors of ~1e-16 per step, so it
// can only mistake the order of crossings at grid corners within ~1e-13 rad of the segment: it visits exactly the
// squares whose interior the segment crosses, besides squares touching such corners.
constexpr double kMargin = 1e-5;

}  // namespace

OcclusionIndex::OcclusionIndex(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds,
                               const Eigen::Vector2d& sensor_grid, double range_cells)
    : occupancy_(occupancy), thresholds_(thresholds), sensor_grid_(sensor_grid) {
  const GridGeometry& g = occupancy.geometry;
  const double sx = sensor_grid.x(), sy = sensor_grid.y();
  start_ix_ = static_cast<int>(std::floor(sx));
  start_iy_ = static_cast<int>(std::floor(sy));
  // The cells a traversal to a cell centre in range can visit: those of ApplyObservation's bounding box.
  const int ix0 = std::max(0, static_cast<int>(std::floor(sx - range_cells)));
  const int ix1 = std::min(g.width_cells - 1, static_cast<int>(std::ceil(sx + range_cells)));
  const int iy0 = std::max(0, static_cast<int>(std::floor(sy - range_cells)));
  const int iy1 = std::min(g.height_cells - 1, static_cast<int>(std::ceil(sy + range_cells)));
  const double reach_sq = (range_cells + 1.0) * (range_cells + 1.0);
  corner_cell_below_blocks_ = sx == start_ix_ && sy == start_iy_ && g.Contains(start_ix_, start_iy_ - 1) &&
                              IsOccupied(occupancy.at(start_ix_, start_iy_ - 1), thresholds);

  // Whether a traversal may step from (x, y) into an occupied cell that is the first obstacle it meets.
  const auto open = [&](int x, int y) {
    return !g.Contains(x, y) || (x == start_ix_ && y == start_iy_) || !IsOccupied(occupancy.at(x, y), thresholds);
  };
  const int occupied_min = thresholds.occupied_min;
  std::vector<int> ring_of;  // floor(d_min) per occluder
  for (int iy = iy0; iy <= iy1; ++iy) {
    const std::int8_t* const row = occupancy.cells.data() + static_cast<std::size_t>(iy) * g.width_cells;
    for (int ix = ix0; ix <= ix1; ++ix) {
      if (row[ix] < occupied_min || (ix == start_ix_ && iy == start_iy_)) continue;
      // A traversal is monotonic in x and y, so it enters (ix, iy) from the neighbour on the sensor's side.
      const bool first_obstacle = (ix != start_ix_ && open(ix + (ix > start_ix_ ? -1 : 1), iy)) ||
                                  (iy != start_iy_ && open(ix, iy + (iy > start_iy_ ? -1 : 1)));
      if (!first_obstacle) continue;
      const double x0 = ix - sx, x1 = x0 + 1.0, y0 = iy - sy, y1 = y0 + 1.0;
      const double near_x = std::max({x0, 0.0, -x1}), near_y = std::max({y0, 0.0, -y1});
      const double d_min_sq = near_x * near_x + near_y * near_y;
      if (d_min_sq > reach_sq) continue;
      const double far_x = std::max(std::abs(x0), std::abs(x1)), far_y = std::max(std::abs(y0), std::abs(y1));
      // The sensor is outside the square's interior, so its corners lie within half a turn of its centre's
      // direction. A corner on the sensor has no direction; the other three span the square.
      const double centre = PseudoAngle(x0 + 0.5, y0 + 0.5);
      double lo_offset = 0.0, hi_offset = 0.0;
      for (const auto& [cx, cy] : {std::pair{x0, y0}, std::pair{x1, y0}, std::pair{x0, y1}, std::pair{x1, y1}}) {
        if (cx == 0.0 && cy == 0.0) continue;
        double offset = PseudoAngle(cx, cy) - centre;
        if (offset > 2.0) offset -= 4.0;
        if (offset < -2.0) offset += 4.0;
        lo_offset = std::min(lo_offset, offset);
        hi_offset = std::max(hi_offset, offset);
      }
      double lo = centre + lo_offset;
      if (lo < 0.0) lo += 4.0;
      if (lo >= 4.0) lo -= 4.0;
      // Rounded up, so that d_max_sq < d_sq implies the whole square is nearer than the target.
      const double d_max_sq = far_x * far_x + far_y * far_y;
      float d_max_sq_up = static_cast<float>(d_max_sq);
      if (d_max_sq_up < d_max_sq) d_max_sq_up = std::nextafter(d_max_sq_up, std::numeric_limits<float>::infinity());
      occluders_.push_back({lo, hi_offset - lo_offset, d_max_sq_up, iy * g.width_cells + ix});
      ring_of.push_back(static_cast<int>(std::sqrt(d_min_sq)));
    }
  }

  // Occluders by ring (counting sort), so each bin's entries come out nearest ring first.
  const int rings = ring_of.empty() ? 1 : *std::max_element(ring_of.begin(), ring_of.end()) + 1;
  std::vector<int> ring_begin(rings + 1, 0);
  for (const int ring : ring_of) ++ring_begin[ring + 1];
  for (int r = 0; r < rings; ++r) ring_begin[r + 1] += ring_begin[r];
  std::vector<int> order(occluders_.size());
  for (std::size_t k = 0; k < occluders_.size(); ++k) order[ring_begin[ring_of[k]]++] = static_cast<int>(k);

  // Bins in unwrapped coordinates u: bin u mod kBins, interval shifted by a turn where u wraps.
  const auto bin_range = [](const Occluder& o) {
    return std::pair{static_cast<int>(std::floor((o.lo - 2.0 * kMargin) * kBinsPerUnit)),
                     static_cast<int>(std::floor((o.lo + o.span + 2.0 * kMargin) * kBinsPerUnit))};
  };
  const auto wrap = [](int u) { return u < 0 ? u + kBins : (u >= kBins ? u - kBins : u); };
  bin_begin_.assign(kBins + 1, 0);
  for (const Occluder& o : occluders_) {
    const auto [u0, u1] = bin_range(o);
    for (int u = u0; u <= u1; ++u) ++bin_begin_[wrap(u) + 1];
  }
  for (int b = 0; b < kBins; ++b) bin_begin_[b + 1] += bin_begin_[b];
  entries_.resize(static_cast<std::size_t>(bin_begin_[kBins]));
  std::vector<int> fill(bin_begin_.begin(), bin_begin_.end() - 1);
  const float inf = std::numeric_limits<float>::infinity();
  cover_sq_.assign(kBins, inf);
  first_ring_sq_.assign(kBins, inf);
  for (const int k : order) {
    const Occluder& o = occluders_[k];
    const auto [u0, u1] = bin_range(o);
    const float ring_sq = static_cast<float>(ring_of[k] * ring_of[k]);
    for (int u = u0; u <= u1; ++u) {
      const double shift = u < 0 ? 4.0 : (u >= kBins ? -4.0 : 0.0);
      const int b = wrap(u);
      const Entry e{o.lo + shift, o.lo + o.span + shift, ring_sq, o.d_max_sq, o.cell, k};
      if (fill[b] == bin_begin_[b]) first_ring_sq_[b] = ring_sq;
      entries_[fill[b]++] = e;
      // A bin holds pseudo-angles in [b, b + 1] / kBinsPerUnit.
      if (e.lo + kMargin < b / kBinsPerUnit && e.hi - kMargin > (b + 1) / kBinsPerUnit) {
        cover_sq_[b] = std::min(cover_sq_[b], o.d_max_sq);
      }
    }
  }
}

// Whether the square `cell`, whose interior the ray from the sensor along (dx, dy) certainly crosses, is crossed
// before the target centre (dx, dy) at squared distance d_sq. The target centre lies >= 0.5 cells from any other
// square, so the crossing is either clearly before it or clearly after.
bool OcclusionIndex::CertainlyBefore(int cell, double dx, double dy, double d_sq, float d_max_sq) const {
  if (d_max_sq < d_sq) return true;
  const int width = occupancy_.geometry.width_cells;
  const double x0 = cell % width - sensor_grid_.x(), y0 = cell / width - sensor_grid_.y();
  const double inf = std::numeric_limits<double>::infinity();
  const double enter_x = dx > 0 ? x0 / dx : (dx < 0 ? (x0 + 1.0) / dx : -inf);
  const double enter_y = dy > 0 ? y0 / dy : (dy < 0 ? (y0 + 1.0) / dy : -inf);
  return std::max(enter_x, enter_y) < 1.0;
}

bool OcclusionIndex::DecideInBin(int ix, int iy, double dx, double dy, double d_sq, double a, int bin) {
  const int target = iy * occupancy_.geometry.width_cells + ix;
  // Neighbouring queries are mostly hidden by the same square.
  if (last_certain_ >= 0) {
    const Occluder& o = occluders_[last_certain_];
    double offset = a - o.lo;
    if (offset < 0.0) offset += 4.0;
    if (o.cell != target && offset > kMargin && offset < o.span - kMargin &&
        CertainlyBefore(o.cell, dx, dy, d_sq, o.d_max_sq)) {
      return true;
    }
  }
  bool undecided = false;
  const Entry* const end = entries_.data() + bin_begin_[bin + 1];
  for (const Entry* e = entries_.data() + bin_begin_[bin]; e != end; ++e) {
    if (e->ring_sq >= d_sq) break;  // this square and all later ones lie beyond the target
    if (e->cell == target) continue;
    if (a > e->lo + kMargin && a < e->hi - kMargin) {
      if (CertainlyBefore(e->cell, dx, dy, d_sq, e->d_max_sq)) {
        last_certain_ = e->occluder;
        return true;
      }
    } else if (a >= e->lo - kMargin && a <= e->hi + kMargin) {
      undecided = true;
    }
  }
  if (!undecided) return false;
  ++exact_fallbacks_;
  return engine::IsOccluded(occupancy_, thresholds_, sensor_grid_, ix, iy);
}

}  // namespace anchordb::engine
