#include "engine/segmentation/geometric_categories.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace anchordb::engine::segmentation {
namespace {

struct Prototype {
  const char* id;
  double height, height_sigma;
  double major, major_sigma;
  double minor, minor_sigma;
  double top, top_sigma;
  double layer, layer_sigma;
};

// One prototype per category of the built-in knowledge table.
constexpr Prototype kPrototypes[] = {
    {"table", 0.74, 0.12, 1.2, 0.5, 0.8, 0.3, 0.55, 0.25, 0.95, 0.12},
    {"chair", 0.90, 0.15, 0.5, 0.15, 0.45, 0.12, 0.3, 0.2, 0.5, 0.15},
    {"armchair", 0.85, 0.15, 0.85, 0.2, 0.8, 0.2, 0.3, 0.2, 0.5, 0.15},
    {"sofa", 0.85, 0.15, 2.0, 0.5, 0.9, 0.2, 0.3, 0.2, 0.5, 0.15},
    {"shelf", 1.8, 0.4, 0.9, 0.4, 0.35, 0.12, 0.15, 0.15, 0.6, 0.4},
    {"wardrobe", 2.0, 0.25, 1.2, 0.4, 0.6, 0.12, 0.15, 0.15, 0.8, 0.4},
    {"cupboard", 0.85, 0.2, 1.2, 0.5, 0.5, 0.15, 0.25, 0.2, 0.9, 0.25},
    {"chest_of_drawers", 0.9, 0.15, 0.9, 0.3, 0.5, 0.12, 0.2, 0.2, 0.9, 0.25},
    {"plant", 1.0, 0.4, 0.45, 0.15, 0.4, 0.15, 0.15, 0.15, 0.6, 0.4},
    {"stool", 0.45, 0.1, 0.4, 0.1, 0.35, 0.1, 0.45, 0.25, 0.95, 0.12},
};

double Term(double x, double mu, double sigma) {
  const double z = (x - mu) / sigma;
  return -0.5 * z * z;
}

}  // namespace

ShapeMeasures MeasureSegment(const FurnitureSegment& s, std::optional<double> floor_z_m) {
  ShapeMeasures m;
  const Footprint& f = s.footprint;
  // The top: the 97th percentile of the heights, so that a bottle standing on a table does not lift it.
  double top_z = f.max_z_m;
  if (!s.points_m.empty()) {
    std::vector<float> z;
    z.reserve(s.points_m.size());
    for (const Eigen::Vector3f& p : s.points_m) z.push_back(p.z());
    const std::size_t k = static_cast<std::size_t>(0.97 * static_cast<double>(z.size() - 1));
    std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(k), z.end());
    top_z = z[k];
  }
  m.height_m = top_z - (floor_z_m ? *floor_z_m : f.min_z_m);
  m.major_m = std::max(f.extent_m.x(), f.extent_m.y());
  m.minor_m = std::min(f.extent_m.x(), f.extent_m.y());
  // The densest 5 cm layer above 0.25 m (a table top, a seat, a board).
  const double base = floor_z_m ? *floor_z_m : f.min_z_m;
  std::map<int, std::size_t> layers;
  for (const Eigen::Vector3f& p : s.points_m) {
    if (p.z() - base > 0.25) ++layers[static_cast<int>(std::floor((p.z() - base) / 0.05))];
  }
  std::size_t densest = 0;
  int layer = -1;
  for (const auto& [k, count] : layers) {
    if (count > densest) densest = count, layer = k;
  }
  m.top_fraction = s.points_m.empty() ? 0.0 : static_cast<double>(densest) / static_cast<double>(s.points_m.size());
  m.layer_ratio = layer >= 0 && m.height_m > 0 ? std::min(1.2, (layer + 0.5) * 0.05 / m.height_m) : 1.0;
  return m;
}

std::vector<double> GeometricCategories(const ShapeMeasures& m, const std::vector<std::string>& ids) {
  std::vector<double> log_score(ids.size(), std::numeric_limits<double>::quiet_NaN());
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ids.size(); ++i) {
    for (const Prototype& p : kPrototypes) {
      if (ids[i] != p.id) continue;
      log_score[i] = Term(m.height_m, p.height, p.height_sigma) + Term(m.major_m, p.major, p.major_sigma) +
                     Term(m.minor_m, p.minor, p.minor_sigma) + Term(m.top_fraction, p.top, p.top_sigma) +
                     Term(m.layer_ratio, p.layer, p.layer_sigma);
      lowest = std::min(lowest, log_score[i]);
    }
  }
  std::vector<double> out(ids.size(), 1.0);
  if (!std::isfinite(lowest)) {
    for (double& v : out) v = 1.0 / static_cast<double>(std::max<std::size_t>(1, ids.size()));
    return out;
  }
  double best = -std::numeric_limits<double>::infinity();
  for (double& v : log_score) {
    if (std::isnan(v)) v = lowest;
    best = std::max(best, v);
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i) sum += out[i] = std::exp(log_score[i] - best);
  for (double& v : out) v /= sum;
  return out;
}

}  // namespace anchordb::engine::segmentation
