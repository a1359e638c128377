#pragma once
// Anchored features (thesis 4.3.2): the feature types and their descriptor lengths, the de-duplication rule (close
// in descriptor space and in 3D), codebooks by k-means and bags of words.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/features/extraction.h"

namespace anchordb::engine {

// Descriptor length of the scene plane descriptor "spd" (engine/features/extraction.h).
inline constexpr int kSpdDims = 8;

// The descriptor length of a known type: fpfh 33, shot 352, spd 8, orb 32, brisk 64, freak 64, sift 128, surf 64.
// Client-defined types are named "x_<name>" (any length, fixed per map by its first feature): nullopt for them.
// Throws Error(kInvalidArgument, "type") for any other name.
std::optional<int> FeatureTypeDims(const std::string& type);

// Two features are duplicates when their anchors are within radius_m [m] and their descriptors within
// descriptor_distance (Euclidean). A threshold of 0 keeps only exact repeats out.
struct DedupThreshold {
  double radius_m = 0.02;
  double descriptor_distance = 0.0;
};
double DescriptorDistance(const std::vector<float>& a, const std::vector<float>& b);
bool IsDuplicate(const std::vector<float>& a, const Eigen::Vector3d& anchor_a_m, const std::vector<float>& b,
                 const Eigen::Vector3d& anchor_b_m, const DedupThreshold& threshold);

// A codebook: `words` centres of `dims` floats, row-major.
struct Codebook {
  int words = 0;
  int dims = 0;
  std::vector<float> centres;
};
// k-means (OpenCV kmeans, k-means++ seeding from `seed`, 3 attempts) over `descriptors` (n x dims row-major).
// Throws Error(kUnprocessable) when there are fewer descriptors than words, and kInvalidArgument for words < 2.
Codebook BuildCodebook(const std::vector<float>& descriptors, int dims, int words, std::uint64_t seed);
// The index of the nearest centre (Euclidean).
int NearestWord(const Codebook& book, const std::vector<float>& descriptor);
// A normalised histogram of codewords over `words` bins (all zero for no codewords).
std::vector<double> BagOfWords(const std::vector<int>& codewords, int words);
// One cloud's bag of words of one feature type (thesis 4.3.2): each feature of `type` whose descriptor has the
// codebook's length coded to its nearest word, then BagOfWords over the codebook's words; `coded` counts them.
struct TypedBag {
  int coded = 0;
  std::vector<double> bag;
};
TypedBag BagOfWordsOfType(const std::vector<ExtractedFeature>& features, const std::string& type, const Codebook& book);

// Whether the point (x, y) lies inside the simple polygon (even-odd rule; map frame [m]).
bool InsidePolygon(const std::vector<Eigen::Vector2d>& polygon_m, const Eigen::Vector2d& p_m);

}  // namespace anchordb::engine
