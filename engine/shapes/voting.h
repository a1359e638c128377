#pragma once
// Internal to engine/shapes: codeword activation (eq. 4.5) and the ray-based Hough voting (eqs. 4.4, 4.7).
#include <vector>

#include <Eigen/Core>

#include "engine/shapes/shape_features.h"
#include "engine/shapes/shape_model.h"

namespace anchordb::engine::shapes_detail {

struct ActivatedWord {
  int word = 0;
  float probability = 0;  // p(c | f): inverse Euclidean distance, normalised over the activated words
};

class WordIndex {
 public:
  WordIndex(const std::vector<float>& codebook, int words, int dims);
  // For each descriptor (n x dims row-major) its `k` nearest words.
  std::vector<std::vector<ActivatedWord>> Activate(const std::vector<float>& descriptors, int k) const;

 private:
  std::vector<float> codebook_;
  std::vector<float> norms_;
  int words_, dims_;
};

// The ray of one bin's middle direction, in the cloud frame: origin + t * direction, t > 0.
struct Ray {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // unit
  int category = 0;
  int keypoint = 0;  // index of the keypoint that casts it (rays come grouped by keypoint)
  float weight = 0;  // eq. 4.7
};
std::vector<Ray> CastRays(const ShapeModel& model, const LocalFeatures& features);

// Per category the weight of a sphere at `centre_m`: each keypoint's rays passing within the sphere radius, in front
// of the keypoint (or starting inside the sphere), add up to its eq. 4.7 weight w for the category (at most 1: the
// codeword's histogram sums to 1 over categories and directions); the sphere sums log(1 + w / floor) over the
// keypoints, i.e. up to a constant the log of the product of the keypoints' (floored) support, so that many
// keypoints agreeing outweigh a few with concentrated votes.
std::vector<double> SphereWeights(const ShapeModel& model, const LocalFeatures& features, const Eigen::Vector3f& centre_m);

// ShapeDetection mode over spheres on a grid spanning the cloud's bounding box.
std::vector<ShapeDetection> DetectSpheres(const ShapeModel& model, const LocalFeatures& features,
                                     const std::vector<Eigen::Vector3f>& points_m);

}  // namespace anchordb::engine::shapes_detail
