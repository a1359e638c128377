// Training and ray-based Hough voting of the shape models (thesis 4.1.1-4.1.2). OpenCV kmeans for the codebook;
// PCL only behind shape_features.h.
#include "engine/shapes/shape_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <opencv2/core.hpp>

#include "engine/shapes/shape_features.h"
#include "engine/shapes/voting.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace {

using shapes_detail::ActivatedWord;
using shapes_detail::kShotDims;
using shapes_detail::LocalFeatures;

void CheckPoints(const std::vector<Eigen::Vector3f>& points_m, const std::string& field) {
  if (points_m.empty()) throw Error(ErrorCode::kUnprocessable, "the cloud is empty", field);
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    if (!points_m[i].allFinite()) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " is not finite (NaN or infinite)", field);
    }
  }
}

Eigen::Vector3f Centroid(const std::vector<Eigen::Vector3f>& points_m) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points_m) sum += p.cast<double>();
  return (sum / static_cast<double>(points_m.size())).cast<float>();
}

int DirectionBin(const Eigen::Vector3f& local, int azimuth_bins, int polar_bins) {
  constexpr double kPi = 3.14159265358979323846;
  double azimuth = std::atan2(local.y(), local.x());
  if (azimuth < 0) azimuth += 2 * kPi;
  const double polar = std::acos(std::clamp(static_cast<double>(local.z()), -1.0, 1.0));
  const int a = std::min(azimuth_bins - 1, static_cast<int>(azimuth / (2 * kPi) * azimuth_bins));
  const int q = std::min(polar_bins - 1, static_cast<int>(polar / kPi * polar_bins));
  return q * azimuth_bins + a;
}

// Per category log(kernel density + floor) of `size` among its training clouds' sizes (log height, length and
// width; Gaussian kernels of width size_bandwidth, the density's peak 1); all 0 when the term is off or a category
// has no training sizes (a version-1 blob).
std::vector<double> SizeLogLikelihoods(const ShapeModel& model, const CloudSize& size) {
  const auto& p = model.params;
  std::vector<double> out(model.categories.size(), 0.0);
  if (!(p.size_weight > 0)) return out;
  for (const auto& c : model.categories) {
    if (c.sizes.empty()) return out;
  }
  constexpr double kMinM = 0.01;  // sizes below 1 cm count as 1 cm (a flat or degenerate cloud)
  const auto logs = [&](const CloudSize& s) {
    return Eigen::Vector3d(std::log(std::max<double>(s.height_m, kMinM)), std::log(std::max<double>(s.length_m, kMinM)),
                           std::log(std::max<double>(s.width_m, kMinM)));
  };
  const Eigen::Vector3d x = logs(size);
  for (std::size_t c = 0; c < model.categories.size(); ++c) {
    double density = 0;
    for (const CloudSize& s : model.categories[c].sizes) {
      density += std::exp(-0.5 * (x - logs(s)).squaredNorm() / (p.size_bandwidth * p.size_bandwidth));
    }
    out[c] = std::log(density / static_cast<double>(model.categories[c].sizes.size()) + p.size_floor);
  }
  return out;
}

bool Report(const ShapeProgress& progress, double fraction, const std::string& stage) {
  if (progress && !progress(fraction, stage)) throw Error(ErrorCode::kConflict, "training was cancelled", "cancelled");
  return true;
}

}  // namespace

void CheckShapeModelParams(const ShapeModelParams& p) {
  const auto positive = [](double v, double hi, const char* field) {
    if (!std::isfinite(v) || v <= 0 || v > hi) {
      throw Error(ErrorCode::kInvalidArgument, std::string(field) + " must be in (0, " + std::to_string(hi) + "]", field);
    }
  };
  positive(p.voxel_m, 1.0, "voxel_m");
  positive(p.normal_radius_m, 2.0, "normal_radius_m");
  positive(p.boundary_angle_rad, 1.5708, "boundary_angle_rad");
  positive(p.keypoint_spacing_m, 2.0, "keypoint_spacing_m");
  positive(p.shot_radius_m, 3.0, "shot_radius_m");
  positive(p.sphere_radius_m, 5.0, "sphere_radius_m");
  positive(p.detection_spacing_m, 5.0, "detection_spacing_m");
  positive(p.accept_fraction, 1.0, "accept_fraction");
  positive(p.merge_distance_m, 20.0, "merge_distance_m");
  if (p.codebook_size < 2 || p.codebook_size > 5000) {
    throw Error(ErrorCode::kInvalidArgument, "codebook_size must be in [2, 5000]", "codebook_size");
  }
  if (p.activated_words < 1 || p.activated_words > 20) {
    throw Error(ErrorCode::kInvalidArgument, "activated_words must be in [1, 20]", "activated_words");
  }
  if (p.azimuth_bins < 1 || p.azimuth_bins > 360) {
    throw Error(ErrorCode::kInvalidArgument, "azimuth_bins must be in [1, 360]", "azimuth_bins");
  }
  if (p.polar_bins < 1 || p.polar_bins > 180) {
    throw Error(ErrorCode::kInvalidArgument, "polar_bins must be in [1, 180]", "polar_bins");
  }
  if (p.max_keypoints < 10 || p.max_keypoints > 100000) {
    throw Error(ErrorCode::kInvalidArgument, "max_keypoints must be in [10, 100000]", "max_keypoints");
  }
  if (!std::isfinite(p.size_weight) || p.size_weight < 0 || p.size_weight > 10) {
    throw Error(ErrorCode::kInvalidArgument, "size_weight must be in [0, 10]", "size_weight");
  }
  positive(p.size_bandwidth, 5.0, "size_bandwidth");
  positive(p.size_floor, 1.0, "size_floor");
}

ShapeModel TrainShapeModel(const std::vector<LabelledCloud>& samples, const ShapeModelParams& params,
                           const ShapeProgress& progress, TrainingReport* report) {
  const auto started = std::chrono::steady_clock::now();
  CheckShapeModelParams(params);
  if (samples.empty()) throw Error(ErrorCode::kInvalidArgument, "there are no training samples", "samples");
  ShapeModel model;
  model.params = params;
  model.descriptor_dims = kShotDims;
  std::vector<int> sample_category(samples.size());
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const std::string field = "samples[" + std::to_string(s) + "]";
    if (samples[s].category.empty()) throw Error(ErrorCode::kInvalidArgument, "a sample has no category", field + ".category");
    CheckPoints(samples[s].points_m, field + ".points");
    if (samples[s].points_m.size() < 10) {
      throw Error(ErrorCode::kUnprocessable, "a sample needs at least 10 points", field + ".points");
    }
    auto it = std::find_if(model.categories.begin(), model.categories.end(),
                           [&](const CategoryModel& c) { return c.name == samples[s].category; });
    if (it == model.categories.end()) {
      model.categories.push_back(CategoryModel{samples[s].category, 0, 0, {}});
      it = model.categories.end() - 1;
    }
    sample_category[s] = static_cast<int>(it - model.categories.begin());
    ++it->samples;
  }

  // 1. Local features of every sample, with the direction from each keypoint to its sample's centroid.
  std::vector<LocalFeatures> features(samples.size());
  std::vector<Eigen::Vector3f> centres(samples.size());
  std::size_t total = 0;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    Report(progress, 0.6 * static_cast<double>(s) / samples.size(), "features");
    features[s] = shapes_detail::ComputeLocalFeatures(samples[s].points_m, params, params.seed + 7919 * s);
    centres[s] = Centroid(samples[s].points_m);
    model.categories[sample_category[s]].sizes.push_back(MeasureCloudSize(samples[s].points_m));
    model.categories[sample_category[s]].keypoints += static_cast<int>(features[s].positions_m.size());
    total += features[s].positions_m.size();
  }
  for (const auto& c : model.categories) {
    if (c.keypoints == 0) {
      throw Error(ErrorCode::kUnprocessable, "category '" + c.name + "' has no keypoints in its samples", "samples");
    }
  }

  // 2. The codebook: k-means (OpenCV, k-means++ seeded, one attempt of at most 30 iterations) over a seeded
  // subsample of at most 20 descriptors per word.
  Report(progress, 0.6, "codebook");
  std::vector<std::pair<std::size_t, std::size_t>> all;  // (sample, keypoint)
  all.reserve(total);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    for (std::size_t k = 0; k < features[s].positions_m.size(); ++k) all.emplace_back(s, k);
  }
  const int words = std::min<int>(params.codebook_size, static_cast<int>(all.size()));
  if (words < 2) throw Error(ErrorCode::kUnprocessable, "the samples give fewer than 2 descriptors", "samples");
  std::vector<std::pair<std::size_t, std::size_t>> pick = all;
  std::mt19937_64 rng(params.seed);
  const std::size_t limit = static_cast<std::size_t>(words) * 20;
  if (pick.size() > limit) {
    std::shuffle(pick.begin(), pick.end(), rng);
    pick.resize(limit);
    std::sort(pick.begin(), pick.end());
  }
  std::vector<float> data;
  data.reserve(pick.size() * kShotDims);
  for (const auto& [s, k] : pick) {
    const float* d = features[s].descriptors.data() + k * kShotDims;
    data.insert(data.end(), d, d + kShotDims);
  }
  {
    const cv::Mat mat(static_cast<int>(pick.size()), kShotDims, CV_32F, data.data());
    cv::Mat labels, words_mat;
    cv::setRNGSeed(static_cast<int>(params.seed & 0x7fffffff));
    cv::kmeans(mat, words, labels, cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 30, 1e-4), 1,
               cv::KMEANS_PP_CENTERS, words_mat);
    model.codebook.assign(words_mat.ptr<float>(0), words_mat.ptr<float>(0) + static_cast<std::size_t>(words) * kShotDims);
  }
  model.params.codebook_size = words;

  // 3. Per category and codeword the histogram of vote directions in the keypoints' local frames, each keypoint
  // adding its activation p(c | f) (eq. 4.5); a category's histograms are normalised to sum 1 over every word
  // and bin, so each bin holds p(direction, word | category) (eq. 4.6 with the word's frequency kept in).
  Report(progress, 0.8, "histograms");
  const int bins = params.azimuth_bins * params.polar_bins;
  std::vector<std::vector<std::vector<float>>> counts(
      model.categories.size(), std::vector<std::vector<float>>(words));
  const shapes_detail::WordIndex index(model.codebook, words, kShotDims);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const auto& f = features[s];
    const auto activations = index.Activate(f.descriptors, params.activated_words);
    auto& category_counts = counts[sample_category[s]];
    for (std::size_t k = 0; k < f.positions_m.size(); ++k) {
      const Eigen::Vector3f to_centre = centres[s] - f.positions_m[k];
      if (to_centre.norm() < 1e-6f) continue;
      const int bin = DirectionBin(f.frames[k] * to_centre.normalized(), params.azimuth_bins, params.polar_bins);
      for (const ActivatedWord& a : activations[k]) {
        auto& h = category_counts[a.word];
        if (h.empty()) h.assign(bins, 0.0f);
        h[bin] += a.probability;
      }
    }
  }
  int non_empty = 0;
  for (std::size_t c = 0; c < model.categories.size(); ++c) {
    double sum = 0;
    for (const auto& h : counts[c]) sum += std::accumulate(h.begin(), h.end(), 0.0);
    auto& out = model.categories[c].words;
    out.assign(words, {});
    for (int w = 0; w < words; ++w) {
      const auto& h = counts[c][w];
      for (int b = 0; b < static_cast<int>(h.size()); ++b) {
        if (h[b] > 0) out[w].push_back(VoteBin{b, static_cast<float>(h[b] / sum)});
      }
      non_empty += static_cast<int>(out[w].size());
    }
  }
  Report(progress, 1.0, "done");
  if (report) {
    report->samples = static_cast<int>(samples.size());
    report->keypoints = static_cast<int>(total);
    report->codebook_size = words;
    report->categories.clear();
    report->samples_per_category.clear();
    report->keypoints_per_category.clear();
    for (const auto& c : model.categories) {
      report->categories.push_back(c.name);
      report->samples_per_category.push_back(c.samples);
      report->keypoints_per_category.push_back(c.keypoints);
    }
    report->non_empty_bins = non_empty;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  return model;
}

Verification VerifyAt(const ShapeModel& model, const std::vector<Eigen::Vector3f>& points_m,
                      const Eigen::Vector3f& centre_m) {
  CheckPoints(points_m, "points");
  Verification out;
  out.centre_m = centre_m;
  const auto f = shapes_detail::ComputeLocalFeatures(points_m, model.params, model.params.seed);
  out.keypoints = static_cast<int>(f.positions_m.size());
  out.size = MeasureCloudSize(points_m);
  const std::vector<double> weights = shapes_detail::SphereWeights(model, f, centre_m);
  const std::vector<double> size_terms = SizeLogLikelihoods(model, out.size);
  const double sum = std::accumulate(weights.begin(), weights.end(), 0.0);
  // p(f) ~ (weight / sum) * p(size | category)^size_weight, in logs; categories without votes keep 0.
  std::vector<double> log_p(weights.size(), -std::numeric_limits<double>::infinity());
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < weights.size(); ++c) {
    if (sum > 0 && weights[c] > 0) log_p[c] = std::log(weights[c] / sum) + model.params.size_weight * size_terms[c];
    top = std::max(top, log_p[c]);
  }
  double norm = 0;
  for (double v : log_p) norm += std::isfinite(top) ? std::exp(v - top) : 0.0;
  for (std::size_t c = 0; c < model.categories.size(); ++c) {
    const double probability = norm > 0 && std::isfinite(log_p[c]) ? std::exp(log_p[c] - top) / norm : 0.0;
    out.scores.push_back(CategoryScore{model.categories[c].name, probability, weights[c], size_terms[c]});
    if (std::isfinite(log_p[c]) && log_p[c] == top && out.best.empty()) out.best = model.categories[c].name;
  }
  return out;
}

Verification Verify(const ShapeModel& model, const std::vector<Eigen::Vector3f>& points_m) {
  CheckPoints(points_m, "points");
  return VerifyAt(model, points_m, Centroid(points_m));
}

std::vector<ShapeDetection> Detect(const ShapeModel& model, const std::vector<Eigen::Vector3f>& room_points_m) {
  CheckPoints(room_points_m, "points");
  const auto f = shapes_detail::ComputeLocalFeatures(room_points_m, model.params, model.params.seed);
  if (f.positions_m.empty()) return {};
  return shapes_detail::DetectSpheres(model, f, room_points_m);
}

}  // namespace anchordb::engine
