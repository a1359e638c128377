#pragma once
// 3D shape models (thesis 4.1): an implicit shape model with ray-based Hough voting. Keypoints on boundaries
// (normal-angle differences), SHOT descriptors (PCL) with their local reference frames, one k-means codebook over
// every category, and per category and codeword a histogram of vote directions (azimuth x polar bins of the
// keypoint's local frame, towards the sample's centre). Prediction casts one ray per non-empty bin of every
// activated codeword; a ray counts for a sphere when it passes within the sphere's radius in front of the keypoint,
// with the weight of eq. 4.7 (p(codeword | feature) * p(category, direction | codeword), the codeword's histogram
// over every category's balanced counts). A sphere's weight for a category sums, over the keypoints, log(1 + w / floor)
// of the keypoint's eq. 4.7 weight w through the sphere (voting.h): agreement of many keypoints, not the mass of a few.
//
// Verification mode: one sphere at the centre of a segment -> p(f) over the categories, times a size term (the
// segment's height and horizontal extents against each category's training clouds; not in the thesis). ShapeDetection mode: spheres on
// a grid over a room cloud; every sphere of any category whose weight is >= 75 % of the global maximum is a
// hypothesis, and neighbours of the same category closer than `merge_distance_m` are merged.
//
// Points in metres, in any frame the caller keeps (the model is scale-free in its votes, but the keypoint and SHOT
// radii are metres) as long as z points up: the size term of verification measures height along z. Only std / Eigen
// types here; PCL and OpenCV stay in the .cc files. Deterministic: the same samples, parameters and seed give the
// same model and the same predictions.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace anchordb::engine {

struct ShapeModelParams {
  double voxel_m = 0.02;             // the cloud is thinned to this voxel size first
  double normal_radius_m = 0.05;     // neighbourhood of the normal estimate
  double boundary_angle_rad = 0.35;  // a point is on a boundary when a neighbour's normal differs by more than this
  double keypoint_spacing_m = 0.05;  // at most one keypoint per voxel of this size (boundary points first)
  double shot_radius_m = 0.40;       // SHOT support radius (thesis: 0.10 m; 0.40 m is best on our furniture views)
  int codebook_size = 1000;          // k-means words over every category's descriptors (thesis: 1000)
  int activated_words = 1;           // codewords a feature activates (eq. 4.5 over these)
  int azimuth_bins = 36;             // vote-direction histogram: azimuth (0..2 pi) x polar (0..pi) bins
  int polar_bins = 18;
  double sphere_radius_m = 0.25;     // radius of a Hough sphere (verification and detection)
  double detection_spacing_m = 0.10; // distance between detection sphere centres
  double accept_fraction = 0.75;     // detection: accept spheres >= this share of the global maximum
  double merge_distance_m = 0.40;    // detection: merge accepted spheres of one category closer than this
  int max_keypoints = 1500;          // per cloud, a seeded subsample beyond this
  std::uint64_t seed = 1;
  // Verification only, a size term (not in the thesis; engine/shapes/README.md): p(f) is the voting share times
  // p(size | category)^size_weight, p(size | category) a Gaussian kernel density over the category's training clouds
  // in log height, log length and log width (CloudSize, z up), kernel width `size_bandwidth` (log units), plus
  // `size_floor` (so that a size no training cloud had costs at most a bounded factor). size_weight 0: votes only.
  double size_weight = 0.5;
  double size_bandwidth = 0.2;
  double size_floor = 0.01;
};

// The size of a cloud, z up (gravity): height = the 1-99 % span of z; length >= width = the 2-98 % spans along the
// principal axes of the horizontal (x, y) spread. Frame-independent otherwise (translation, rotation about z).
struct CloudSize {
  float height_m = 0;
  float length_m = 0;
  float width_m = 0;
};
CloudSize MeasureCloudSize(const std::vector<Eigen::Vector3f>& points_m);

struct LabelledCloud {
  std::string category;
  std::vector<Eigen::Vector3f> points_m;
};

// Per category, per codeword: the vote-direction histogram (azimuth x polar, counts). Only non-empty bins are kept.
struct VoteBin {
  int bin = 0;        // polar_index * azimuth_bins + azimuth_index
  float weight = 0;   // p(direction | codeword) within the category (eq. 4.6), the category's histograms summing to 1
};
struct CategoryModel {
  std::string name;
  int samples = 0;
  int keypoints = 0;
  std::vector<std::vector<VoteBin>> words;  // codebook_size entries
  std::vector<CloudSize> sizes;              // per training cloud (blob version 2; empty from a version-1 blob)
};

struct ShapeModel {
  ShapeModelParams params;
  int descriptor_dims = 352;
  std::vector<float> codebook;  // codebook_size x descriptor_dims, row-major
  std::vector<CategoryModel> categories;
};

struct TrainingReport {
  int samples = 0;
  int keypoints = 0;
  int codebook_size = 0;
  std::vector<std::string> categories;
  std::vector<int> samples_per_category;
  std::vector<int> keypoints_per_category;
  int non_empty_bins = 0;  // over all categories and words
  double seconds = 0;      // wall time of training (a figure, never a decision input)
};

// Progress callback: fraction done in [0, 1] and a short stage name; return false to cancel (throws
// Error(kConflict, "cancelled")). May be empty.
using ShapeProgress = std::function<bool(double fraction, const std::string& stage)>;

// Trains on labelled clouds. Throws Error(kInvalidArgument) for parameters out of range (field named), no samples,
// an empty category name; Error(kUnprocessable) for a sample with non-finite points or fewer than 10 points (field
// "samples[i]"), a category whose samples give no keypoint ("category 'x' has no keypoints"), fewer descriptors
// than codebook words (the codebook shrinks to the descriptor count if at least 2), or fewer than 1 category.
ShapeModel TrainShapeModel(const std::vector<LabelledCloud>& samples, const ShapeModelParams& params,
                           const ShapeProgress& progress = {}, TrainingReport* report = nullptr);

struct CategoryScore {
  std::string category;
  double probability = 0;  // p(f): the category's sphere weight / the sum over categories (0 for all if no votes)
  double weight = 0;       // the sphere's weight: sum over keypoints of log(1 + w / floor), w their eq. 4.7 weights
  double size_log_likelihood = 0;  // log(kernel density + size_floor) of the cloud's size (0 when the term is off)
};
struct Verification {
  Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();  // sphere centre: the centroid of the segment
  std::vector<CategoryScore> scores;                   // in the model's category order
  std::string best;                                    // the most probable category ("" when no ray voted)
  int keypoints = 0;
  CloudSize size;                                      // of the segment
};

// Verification mode. Throws Error(kUnprocessable, "points") for an empty cloud or one with non-finite points.
// A cloud that gives no keypoint answers every probability 0 and best "". probability is the voting share
// weight / sum times exp(size_weight * size_log_likelihood), normalised over the categories; the size term is used
// when size_weight > 0 and every category has training sizes (a version-1 blob has none: votes only).
Verification Verify(const ShapeModel& model, const std::vector<Eigen::Vector3f>& segment_points_m);
// The same with the sphere at a given centre.
Verification VerifyAt(const ShapeModel& model, const std::vector<Eigen::Vector3f>& segment_points_m,
                      const Eigen::Vector3f& centre_m);

struct ShapeDetection {
  std::string category;
  Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();  // weight-weighted mean of the merged sphere centres
  double weight = 0;                                   // the strongest merged sphere's weight
  double relative_weight = 0;                          // weight / global maximum
  int merged_spheres = 0;
};

// ShapeDetection mode over a room cloud, strongest first. Same errors as Verify; no keypoint -> no detection.
std::vector<ShapeDetection> Detect(const ShapeModel& model, const std::vector<Eigen::Vector3f>& room_points_m);

// Versioned binary (de)serialisation ("ANCHSHM2": version 1 plus the size parameters and the training sizes);
// decoding reads "ANCHSHM1" too (size_weight 0, no sizes), checks sizes and throws Error(kInvalidArgument,
// "model") for truncated or foreign bytes. Encode(Decode(b)) == b for version-2 bytes (version 1 is re-encoded as 2).
std::string EncodeShapeModel(const ShapeModel& model);
ShapeModel DecodeShapeModel(std::string_view bytes);

// Checks parameters (used by training and by services before a job starts). Throws Error(kInvalidArgument, field).
void CheckShapeModelParams(const ShapeModelParams& params);

}  // namespace anchordb::engine
