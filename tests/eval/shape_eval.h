#pragma once
// Shape models (issue 16, thesis 4.1.3) side by side with PCL's ISM on the same data, verification mode (one sphere
// at the test cloud's centroid; PCL: its strongest peak and its density at the centroid, the better of the two).
//  (a) PCL's test pair ../shared/data/pcl_test/ism_train.pcd / ism_test.pcd (centimetres, scaled to metres) against
//      a second class from the same folder, the Stanford bunny: train bun0.pcd, test bun4.pcd (another scan),
//      scaled x10 to a similar size; each test cloud in seeded variants (subsample, noise, a cut-away part).
//  (b) the furniture meshes of ../shared/data/aws_small_house/furniture_converted: train on the engine's virtual
//      scans from 12 views (noiseless), test on other views (azimuths between the training ones, other elevations
//      and distances) with the sim's Kinect noise (sim/sensor_artefacts.h), partial views and clutter (a floor
//      patch and a box beside the piece). Leave-one-mesh-out for the categories with several meshes.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "engine/shapes/pcl_ism_peer.h"
#include "engine/shapes/shape_model.h"

namespace anchordb::eval {

struct Confusion {
  std::vector<std::string> categories;
  std::vector<std::vector<int>> counts;  // [true][predicted]; a column "none" at the end for no answer
  int Total() const;
  double Accuracy() const;
  double CategoryAccuracy(std::size_t c) const;
};

struct MethodResult {
  Confusion confusion;
  double train_s = 0;
  double predict_s_per_sample = 0;
};

struct DatasetResult {
  std::string name;
  MethodResult ours;
  MethodResult pcl;
  bool ran_pcl = false;
};

struct ShapeEvalConfig {
  engine::ShapeModelParams params;       // (b)
  engine::ShapeModelParams pair_params;  // (a): its clouds are sparse (the bunny has 397 points)
  engine::PclIsmParams pcl;       // (b)
  engine::PclIsmParams pair_pcl;  // (a): the tutorial's values scaled to metres
  bool run_pcl = true;
  bool train_noise = true;          // (b): training scans with the sim's sensor noise
  int variants_per_test_cloud = 8;  // (a)
  int test_views_per_mesh = 6;      // (b): per mesh
  std::vector<std::string> categories;  // (b): empty = all
  // (b) leave-one-mesh-out: only the held-out meshes [loo_first, loo_first + loo_count) of those in categories with
  // several meshes (sorted by category and name; -1: all), so that a long run can be split.
  int loo_first = 0;
  int loo_count = -1;
  std::uint64_t seed = 16;
};

// A configuration for a quick run (ctest) and the full one (the program).
ShapeEvalConfig QuickShapeEvalConfig();
ShapeEvalConfig FullShapeEvalConfig();

// (a); throws std::runtime_error naming the file when the data is missing.
DatasetResult EvaluatePclTestPair(const ShapeEvalConfig& config);
// (b) unseen views of the training meshes.
DatasetResult EvaluateFurnitureViews(const ShapeEvalConfig& config);
// (b) leave-one-mesh-out: per mesh of a category with several meshes, trained on every other mesh.
DatasetResult EvaluateFurnitureLeaveOneMeshOut(const ShapeEvalConfig& config);

// Whether the shared data of (a) / (b) is present.
bool PclTestPairPresent();
bool FurnitureMeshesPresent();

// Tuning aid: trains once on the furniture scans, then writes one JSON line per training cloud (its size figures)
// and per test cloud of each seed (truth, per-category sphere weights, keypoints, size figures).
// With `leave_one_out`: per mesh of a category with several, the model trained without it on that mesh's test views
// of seeds[0].
void DumpFurnitureViews(const ShapeEvalConfig& config, const std::vector<std::uint64_t>& seeds, std::ostream& out,
                        bool leave_one_out = false);

std::string ResultTable(const DatasetResult& r);  // Markdown: accuracy per category, ours beside PCL, confusion
std::string ResultJson(const DatasetResult& r);

}  // namespace anchordb::eval
