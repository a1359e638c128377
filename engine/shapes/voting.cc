#include "engine/shapes/voting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "schema/error.h"

namespace anchordb::engine::shapes_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// ShapeDetection: rays are followed this far from their keypoint (a furniture centre lies within it of its surface).
constexpr float kMaxRayLengthM = 2.5f;
// ShapeDetection: at most this many spheres per category (the spacing grows for a larger cloud).
constexpr std::size_t kMaxSpheres = 400000;
// A keypoint's rays through a sphere add up to w <= 1 per category (eq. 4.7); the sphere gains log(1 + w / floor)
// for the category (see voting.h). The floor is the weight below which a keypoint's support counts for little.
constexpr double kEvidenceFloor = 0.001;

double Evidence(double keypoint_weight) { return std::log1p(keypoint_weight / kEvidenceFloor); }

// The middle direction of a bin in the local frame.
Eigen::Vector3f BinDirection(int bin, int azimuth_bins, int polar_bins) {
  const int a = bin % azimuth_bins;
  const int q = bin / azimuth_bins;
  const double azimuth = (a + 0.5) * 2 * kPi / azimuth_bins;
  const double polar = (q + 0.5) * kPi / polar_bins;
  return Eigen::Vector3f(static_cast<float>(std::sin(polar) * std::cos(azimuth)),
                         static_cast<float>(std::sin(polar) * std::sin(azimuth)), static_cast<float>(std::cos(polar)));
}

}  // namespace

WordIndex::WordIndex(const std::vector<float>& codebook, int words, int dims)
    : codebook_(codebook), norms_(words), words_(words), dims_(dims) {
  for (int w = 0; w < words; ++w) {
    const Eigen::Map<const Eigen::VectorXf> c(codebook_.data() + static_cast<std::size_t>(w) * dims, dims);
    norms_[w] = c.squaredNorm();
  }
}

std::vector<std::vector<ActivatedWord>> WordIndex::Activate(const std::vector<float>& descriptors, int k) const {
  const std::size_t n = descriptors.size() / static_cast<std::size_t>(dims_);
  std::vector<std::vector<ActivatedWord>> out(n);
  if (n == 0) return out;
  using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMatrix> d(descriptors.data(), static_cast<Eigen::Index>(n), dims_);
  const Eigen::Map<const RowMatrix> c(codebook_.data(), words_, dims_);
  const Eigen::MatrixXf dots = d * c.transpose();
  const int kk = std::min(k, words_);
  std::vector<std::pair<float, int>> dist(words_);
  for (std::size_t i = 0; i < n; ++i) {
    const float di = d.row(static_cast<Eigen::Index>(i)).squaredNorm();
    for (int w = 0; w < words_; ++w) {
      dist[w] = {std::sqrt(std::max(0.0f, di + norms_[w] - 2 * dots(static_cast<Eigen::Index>(i), w))), w};
    }
    std::partial_sort(dist.begin(), dist.begin() + kk, dist.end());
    double sum = 0;
    for (int j = 0; j < kk; ++j) sum += 1.0 / (dist[j].first + 1e-6);
    for (int j = 0; j < kk; ++j) {
      out[i].push_back(ActivatedWord{dist[j].second, static_cast<float>(1.0 / (dist[j].first + 1e-6) / sum)});
    }
  }
  return out;
}

std::vector<Ray> CastRays(const ShapeModel& model, const LocalFeatures& f) {
  const auto& p = model.params;
  const int words = static_cast<int>(model.codebook.size() / static_cast<std::size_t>(model.descriptor_dims));
  const WordIndex index(model.codebook, words, model.descriptor_dims);
  const auto activations = index.Activate(f.descriptors, p.activated_words);
  std::vector<Eigen::Vector3f> directions(static_cast<std::size_t>(p.azimuth_bins) * p.polar_bins);
  for (std::size_t b = 0; b < directions.size(); ++b) {
    directions[b] = BinDirection(static_cast<int>(b), p.azimuth_bins, p.polar_bins);
  }
  // Eq. 4.6 over a codeword's whole histogram: its (category, direction) bins, each category's counts being
  // normalised to sum 1 over its words at training (so that a category with more meshes or keypoints does not
  // outvote the others).
  std::vector<double> word_total(static_cast<std::size_t>(words), 0.0);
  for (const CategoryModel& c : model.categories) {
    for (int w = 0; w < words && w < static_cast<int>(c.words.size()); ++w) {
      for (const VoteBin& v : c.words[w]) word_total[w] += v.weight;
    }
  }
  std::vector<Ray> rays;
  for (std::size_t k = 0; k < f.positions_m.size(); ++k) {
    const Eigen::Matrix3f to_cloud = f.frames[k].transpose();  // local -> cloud frame
    for (const ActivatedWord& a : activations[k]) {
      if (!(word_total[a.word] > 0)) continue;
      for (std::size_t c = 0; c < model.categories.size(); ++c) {
        for (const VoteBin& v : model.categories[c].words[a.word]) {
          rays.push_back(Ray{f.positions_m[k], to_cloud * directions[v.bin], static_cast<int>(c),
                             static_cast<int>(k), static_cast<float>(a.probability * v.weight / word_total[a.word])});
        }
      }
    }
  }
  return rays;
}

std::vector<double> SphereWeights(const ShapeModel& model, const LocalFeatures& f, const Eigen::Vector3f& centre_m) {
  std::vector<double> weights(model.categories.size(), 0.0), keypoint(model.categories.size(), 0.0);
  const float r = static_cast<float>(model.params.sphere_radius_m);
  const auto flush = [&] {
    for (std::size_t c = 0; c < weights.size(); ++c) {
      if (keypoint[c] > 0) weights[c] += Evidence(keypoint[c]);
      keypoint[c] = 0;
    }
  };
  int current = -1;
  for (const Ray& ray : CastRays(model, f)) {  // grouped by keypoint
    if (ray.keypoint != current) {
      flush();
      current = ray.keypoint;
    }
    const Eigen::Vector3f to_centre = centre_m - ray.origin;
    const float along = to_centre.dot(ray.direction);
    const bool inside = to_centre.squaredNorm() <= r * r;
    if (!inside && (along <= 0 || to_centre.cross(ray.direction).squaredNorm() > r * r)) continue;  // eq. 4.4
    keypoint[ray.category] += ray.weight;
  }
  flush();
  return weights;
}

std::vector<ShapeDetection> DetectSpheres(const ShapeModel& model, const LocalFeatures& f,
                                     const std::vector<Eigen::Vector3f>& points_m) {
  const auto& p = model.params;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (const auto& q : points_m) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  float spacing = static_cast<float>(p.detection_spacing_m);
  Eigen::Vector3i cells;
  for (;;) {
    cells = ((hi - lo) / spacing).array().floor().cast<int>() + 1;
    if (static_cast<std::size_t>(cells.x()) * cells.y() * cells.z() <= kMaxSpheres) break;
    spacing *= 1.25f;
  }
  const std::size_t n_cells = static_cast<std::size_t>(cells.x()) * cells.y() * cells.z();
  const std::size_t n_categories = model.categories.size();
  std::vector<double> accumulator(n_cells * n_categories, 0.0);
  std::vector<std::int64_t> last_ray(n_cells, -1);
  const float r = static_cast<float>(p.sphere_radius_m);
  const int reach = static_cast<int>(std::ceil((r + 0.5f * spacing) / spacing));
  const auto centre_of = [&](int x, int y, int z) {
    return Eigen::Vector3f(lo.x() + (x + 0.5f) * spacing, lo.y() + (y + 0.5f) * spacing, lo.z() + (z + 0.5f) * spacing);
  };
  const std::vector<Ray> rays = CastRays(model, f);
  // One keypoint's weights per (sphere, category), turned into evidence when its rays are done.
  std::unordered_map<std::size_t, double> keypoint;
  const auto flush = [&] {
    for (const auto& [slot, w] : keypoint) accumulator[slot] += Evidence(w);
    keypoint.clear();
  };
  for (std::size_t ri = 0; ri < rays.size(); ++ri) {
    const Ray& ray = rays[ri];
    if (ri > 0 && ray.keypoint != rays[ri - 1].keypoint) flush();
    for (float t = 0; t <= kMaxRayLengthM; t += spacing) {
      const Eigen::Vector3f q = ray.origin + t * ray.direction;
      if ((q.array() < lo.array() - r).any() || (q.array() > hi.array() + r).any()) break;
      const Eigen::Vector3i cell = ((q - lo) / spacing).array().floor().cast<int>();
      for (int x = std::max(0, cell.x() - reach); x <= std::min(cells.x() - 1, cell.x() + reach); ++x) {
        for (int y = std::max(0, cell.y() - reach); y <= std::min(cells.y() - 1, cell.y() + reach); ++y) {
          for (int z = std::max(0, cell.z() - reach); z <= std::min(cells.z() - 1, cell.z() + reach); ++z) {
            const std::size_t id = (static_cast<std::size_t>(x) * cells.y() + y) * cells.z() + z;
            if (last_ray[id] == static_cast<std::int64_t>(ri)) continue;
            const Eigen::Vector3f to_centre = centre_of(x, y, z) - ray.origin;
            const bool inside = to_centre.squaredNorm() <= r * r;
            if (!inside && (to_centre.dot(ray.direction) <= 0 || to_centre.cross(ray.direction).squaredNorm() > r * r)) continue;
            last_ray[id] = static_cast<std::int64_t>(ri);
            keypoint[id * n_categories + ray.category] += ray.weight;
          }
        }
      }
    }
  }
  flush();
  const double global_max = *std::max_element(accumulator.begin(), accumulator.end());
  if (!(global_max > 0)) return {};
  struct Sphere {
    std::size_t cell;
    int category;
    double weight;
  };
  std::vector<Sphere> accepted;
  for (std::size_t i = 0; i < accumulator.size(); ++i) {
    if (accumulator[i] >= p.accept_fraction * global_max) {
      accepted.push_back(Sphere{i / n_categories, static_cast<int>(i % n_categories), accumulator[i]});
    }
  }
  std::stable_sort(accepted.begin(), accepted.end(), [](const Sphere& a, const Sphere& b) { return a.weight > b.weight; });
  const auto position = [&](std::size_t cell) {
    const int z = static_cast<int>(cell % cells.z());
    const int y = static_cast<int>((cell / cells.z()) % cells.y());
    const int x = static_cast<int>(cell / cells.z() / cells.y());
    return centre_of(x, y, z);
  };
  std::vector<char> used(accepted.size(), 0);
  std::vector<ShapeDetection> out;
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    if (used[i]) continue;
    const Eigen::Vector3f seed_m = position(accepted[i].cell);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double total = 0;
    int merged = 0;
    for (std::size_t j = i; j < accepted.size(); ++j) {
      if (used[j] || accepted[j].category != accepted[i].category) continue;
      const Eigen::Vector3f at = position(accepted[j].cell);
      if ((at - seed_m).norm() > p.merge_distance_m) continue;
      used[j] = 1;
      sum += accepted[j].weight * at.cast<double>();
      total += accepted[j].weight;
      ++merged;
    }
    ShapeDetection d;
    d.category = model.categories[accepted[i].category].name;
    d.centre_m = (sum / total).cast<float>();
    d.weight = accepted[i].weight;
    d.relative_weight = accepted[i].weight / global_max;
    d.merged_spheres = merged;
    out.push_back(d);
  }
  return out;
}

}  // namespace anchordb::engine::shapes_detail
