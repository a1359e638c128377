#pragma once
// Many line-of-sight queries from one sensor position, with exactly the results of IsOccluded (observation.h).
//
// The occupied cells that can be the first obstacle a traversal meets (those with a free, unknown, off-grid or
// start-cell neighbour on the sensor's side) are indexed by the interval of pseudo-angles (the "diamond angle",
// a monotonic stand-in for atan2) their squares span as seen from the sensor, in fixed angular bins sorted by
// distance. A query decides from the index when the segment to the target centre certainly crosses an indexed
// square's interior, or certainly passes clear of every one; only when it passes within a safety margin of a
// square's silhouette corner does it run the exact IsOccluded traversal, which stays the arbiter.
#include <algorithm>
#include <vector>

#include "engine/grid/grid.h"

namespace anchordb::engine {

class OcclusionIndex {
 public:
  // Indexes the occupied cells of `occupancy` near the segments from `sensor_grid` (continuous grid coordinates,
  // in cells) to every cell centre within `range_cells` of it. `occupancy` is referenced, not copied: it must
  // outlive the index and stay unchanged.
  OcclusionIndex(const OccupancyGrid& occupancy, const OccupancyThresholds& thresholds,
                 const Eigen::Vector2d& sensor_grid, double range_cells);

  // Equals IsOccluded(occupancy, thresholds, sensor_grid, ix, iy) for every cell (ix, iy) whose centre is within
  // `range_cells` of the sensor (occupied or not). Not const: it remembers the last certain occluder.
  bool IsOccluded(int ix, int iy) {
    if (ix == start_ix_ && iy == start_iy_) return false;
    const double dx = ix + 0.5 - sensor_grid_.x(), dy = iy + 0.5 - sensor_grid_.y();
    if (corner_cell_below_blocks_ && dx < 0 && dy < 0) return true;
    const double d_sq = dx * dx + dy * dy;
    const double a = PseudoAngle(dx, dy);
    const int bin = std::min(kBins - 1, static_cast<int>(a * kBinsPerUnit));
    if (d_sq > cover_sq_[bin]) return true;
    if (d_sq <= first_ring_sq_[bin]) return false;
    return DecideInBin(ix, iy, dx, dy, d_sq, a, bin);
  }

  // How many queries fell back to the exact traversal (for tests and benchmarks).
  std::size_t exact_fallbacks() const { return exact_fallbacks_; }

 private:
  struct Occluder {
    double lo = 0.0;     // pseudo-angle [0, 4) of the interval's clockwise end
    double span = 0.0;   // interval length, < 2 (half a turn)
    float d_max_sq = 0;  // squared distance of the farthest corner [cells^2]
    int cell = 0;        // iy * width + ix
  };
  struct Entry {         // one occluder registered in one bin
    double lo = 0.0;     // interval in the bin's frame (shifted by a full turn where the bin wraps)
    double hi = 0.0;
    float ring_sq = 0;   // floor(nearest distance)^2 [cells^2]; entries of a bin ascend in it
    float d_max_sq = 0;
    int cell = 0;
    int occluder = 0;    // index into occluders_
  };

  // Pseudo-angles run over [0, 4) for a full turn; a power-of-two bin count keeps a * kBinsPerUnit exact.
  static constexpr int kBins = 2048;
  static constexpr double kBinsPerUnit = kBins / 4.0;

  // The "diamond angle" of (dx, dy) != 0: monotonic in the angle, 0 along +x, 1 along +y, 2 along -x, 3 along -y.
  static double PseudoAngle(double dx, double dy) {
    if (dy >= 0) return dx >= 0 ? dy / (dx + dy) : 1.0 - dx / (dy - dx);
    return dx < 0 ? 2.0 - dy / (-dx - dy) : 3.0 + dx / (dx - dy);
  }
  // The queries the per-bin bounds leave open: the bin's squares one by one, the traversal if still undecided.
  bool DecideInBin(int ix, int iy, double dx, double dy, double d_sq, double a, int bin);
  bool CertainlyBefore(int cell, double dx, double dy, double d_sq, float d_max_sq) const;

  const OccupancyGrid& occupancy_;
  const OccupancyThresholds thresholds_;
  Eigen::Vector2d sensor_grid_ = Eigen::Vector2d::Zero();
  int start_ix_ = 0;
  int start_iy_ = 0;
  // The sensor sits exactly on a cell corner and the cell below the start cell is occupied: a traversal towards
  // the lower left meets the corner with t_max_x == t_max_y == 0, steps in y first and stops there.
  bool corner_cell_below_blocks_ = false;
  std::vector<Occluder> occluders_;
  std::vector<int> bin_begin_;      // entries of bin b: [bin_begin_[b], bin_begin_[b + 1])
  std::vector<Entry> entries_;
  // Per bin: targets at a squared distance above cover_sq_ are hidden by a square spanning the whole bin;
  // targets at or below first_ring_sq_ lie before every square of the bin [cells^2].
  std::vector<float> cover_sq_;
  std::vector<float> first_ring_sq_;
  int last_certain_ = -1;           // occluder that decided the previous occluded query
  std::size_t exact_fallbacks_ = 0;
};

}  // namespace anchordb::engine
