#include "engine/features/features.h"

#include <cmath>
#include <limits>
#include <map>

#include <opencv2/core.hpp>

#include "schema/error.h"

namespace anchordb::engine {

std::optional<int> FeatureTypeDims(const std::string& type) {
  static const std::map<std::string, int> kKnown = {{"fpfh", 33}, {"shot", 352}, {"spd", kSpdDims}, {"orb", 32},
                                                     {"brisk", 64}, {"freak", 64}, {"sift", 128}, {"surf", 64}};
  if (auto it = kKnown.find(type); it != kKnown.end()) return it->second;
  const bool client = type.size() > 2 && type.size() <= 34 && type.rfind("x_", 0) == 0 &&
                      type.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_", 2) == std::string::npos;
  if (client) return std::nullopt;
  throw Error(ErrorCode::kInvalidArgument,
              "unknown feature type '" + type.substr(0, 40) + "' (fpfh, shot, spd, orb, brisk, freak, sift, surf, or x_<name>)",
              "type");
}

double DescriptorDistance(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    sum += d * d;
  }
  return std::sqrt(sum);
}

bool IsDuplicate(const std::vector<float>& a, const Eigen::Vector3d& anchor_a_m, const std::vector<float>& b,
                 const Eigen::Vector3d& anchor_b_m, const DedupThreshold& t) {
  return (anchor_a_m - anchor_b_m).norm() <= t.radius_m && DescriptorDistance(a, b) <= t.descriptor_distance;
}

Codebook BuildCodebook(const std::vector<float>& descriptors, int dims, int words, std::uint64_t seed) {
  if (words < 2 || words > 10000) throw Error(ErrorCode::kInvalidArgument, "words must be in [2, 10000]", "words");
  if (dims < 1 || descriptors.size() % static_cast<std::size_t>(dims) != 0) {
    throw Error(ErrorCode::kInvalidArgument, "descriptors do not fit their length", "type");
  }
  const int n = static_cast<int>(descriptors.size() / static_cast<std::size_t>(dims));
  if (n < words) {
    throw Error(ErrorCode::kUnprocessable, "a codebook of " + std::to_string(words) + " words needs at least as many features (" +
                                               std::to_string(n) + " stored)", "words");
  }
  const cv::Mat data(n, dims, CV_32F, const_cast<float*>(descriptors.data()));
  cv::Mat labels, centres;
  cv::setRNGSeed(static_cast<int>(seed & 0x7fffffff));
  cv::kmeans(data, words, labels, cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, 100, 1e-4), 3,
             cv::KMEANS_PP_CENTERS, centres);
  Codebook book;
  book.words = words;
  book.dims = dims;
  book.centres.assign(centres.ptr<float>(0), centres.ptr<float>(0) + static_cast<std::size_t>(words) * dims);
  return book;
}

int NearestWord(const Codebook& book, const std::vector<float>& d) {
  int best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int w = 0; w < book.words; ++w) {
    const float* c = book.centres.data() + static_cast<std::size_t>(w) * book.dims;
    double d2 = 0.0;
    for (int j = 0; j < book.dims; ++j) {
      const double diff = static_cast<double>(d[static_cast<std::size_t>(j)]) - c[j];
      d2 += diff * diff;
    }
    if (d2 < best_d2) {
      best_d2 = d2;
      best = w;
    }
  }
  return best;
}

std::vector<double> BagOfWords(const std::vector<int>& codewords, int words) {
  std::vector<double> h(static_cast<std::size_t>(std::max(words, 0)), 0.0);
  int counted = 0;
  for (int w : codewords) {
    if (w < 0 || w >= words) continue;
    h[static_cast<std::size_t>(w)] += 1.0;
    ++counted;
  }
  if (counted > 0) for (double& v : h) v /= counted;
  return h;
}

TypedBag BagOfWordsOfType(const std::vector<ExtractedFeature>& features, const std::string& type, const Codebook& book) {
  std::vector<int> words;
  for (const ExtractedFeature& f : features) {
    if (f.type == type && static_cast<int>(f.descriptor.size()) == book.dims) words.push_back(NearestWord(book, f.descriptor));
  }
  return {static_cast<int>(words.size()), BagOfWords(words, book.words)};
}

bool InsidePolygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace anchordb::engine
