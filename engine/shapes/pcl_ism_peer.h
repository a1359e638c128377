#pragma once
// PCL's own implicit shape model (pcl::ism::ImplicitShapeModelEstimation, PCL 1.13; Knopp et al. 2010: FPFH
// codebook, one vote vector per training feature, mean-shift peaks) behind std / Eigen types: the peer of
// engine/shapes/shape_model.h in the evaluation (tests/eval) and the bench. Not used by the server.
// Parameters as in PCL's tutorial (normals 25, FPFH 30, sampling 2.0 in the tutorial's centimetres) scaled to
// metres. Note: PCL's k-means seeds rand() from time(nullptr), so its codebook is not reproducible across runs.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/shapes/shape_model.h"

namespace anchordb::engine {

struct PclIsmParams {
  double normal_radius_m = 0.25;
  double fpfh_radius_m = 0.30;
  double sampling_m = 0.02;
  int clusters = 184;  // PCL's default number of codebook clusters
};

struct PclIsmResult {
  std::string best;                  // "" when no class got a vote
  std::vector<double> peak_density;  // per category: the strongest peak (PCL's findStrongestPeaks)
  std::vector<double> centre_density;  // per category: vote density at the cloud's centroid (verification mode)
  std::size_t dropped_votes = 0;       // votes of strength 0 or non-finite, dropped before the peak search
};

class PclIsm {
 public:
  PclIsm(const std::vector<LabelledCloud>& samples, const PclIsmParams& params);
  ~PclIsm();
  PclIsm(const PclIsm&) = delete;
  PclIsm& operator=(const PclIsm&) = delete;
  // `by_centre`: decide by the density at the centroid (verification) instead of the strongest peak.
  PclIsmResult Classify(const std::vector<Eigen::Vector3f>& points_m, bool by_centre) const;
  const std::vector<std::string>& categories() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anchordb::engine
