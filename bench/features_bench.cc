// Anchored features and E-SAMME (issue 15, SPEC section 7): feature extraction per 640x480 keyframe (a rendered
// apartment setting, Kinect-like sensor), per type and all three; E-SAMME prediction latency per sample.
#include <benchmark/benchmark.h>

#include <random>

#include "engine/classification/esamme.h"
#include "engine/features/extraction.h"
#include "engine/scene/projection.h"
#include "sim/apartment.h"

namespace {

using namespace anchordb;

const std::vector<Eigen::Vector3f>& KeyframeCloud(Eigen::Vector3d* eye) {
  static Eigen::Vector3d origin;
  static const std::vector<Eigen::Vector3f> cloud = [] {
    const sim::SettingScene s = sim::MakeSetting(sim::AllSettings().front(), 1);
    const PinholeIntrinsics K = sim::KinectIntrinsics();
    const sim::Frame f = sim::Render(s.scene, K, s.X_WorldCameraA, sim::SensorModel{}, 7);
    origin = s.X_WorldCameraA.translation();
    return engine::BackProjectRaw(f.depth_mm, 1000.0, K, s.X_WorldCameraA);
  }();
  *eye = origin;
  return cloud;
}

void BM_ExtractKeyframe(benchmark::State& state, std::vector<std::string> types) {
  Eigen::Vector3d eye;
  const auto& cloud = KeyframeCloud(&eye);
  std::size_t features = 0;
  for (auto _ : state) {
    const auto out = engine::ExtractFeatures(cloud, eye, types, engine::ExtractionParams{});
    features = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["features"] = static_cast<double>(features);
}
BENCHMARK_CAPTURE(BM_ExtractKeyframe, fpfh, std::vector<std::string>{"fpfh"})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ExtractKeyframe, shot, std::vector<std::string>{"shot"})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ExtractKeyframe, spd, std::vector<std::string>{"spd"})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ExtractKeyframe, all, std::vector<std::string>{"fpfh", "shot", "spd"})->Unit(benchmark::kMillisecond);

// A model over 6 classes of 64-dimensional Gaussians (digits-sized): stumps and depth-3 trees (an RBF SVM fits this
// training set exactly and ends boosting after its round), 50
// rounds asked (the counter says how many it kept).
void BM_PredictPerSample(benchmark::State& state) {
  std::mt19937_64 rng(1);
  std::normal_distribution<float> n(0.0f, 1.0f);
  engine::TrainingSet data;
  data.feature_types = {"x"};
  engine::FeatureMatrix x(600, 64);
  for (int i = 0; i < 600; ++i) {
    data.labels.push_back(i % 6);
    for (int d = 0; d < 64; ++d) x(i, d) = n(rng) + (d % 6 == i % 6 ? 1.5f : 0.0f);
  }
  data.features = {x};
  for (int c = 0; c < 6; ++c) data.class_names.push_back("c" + std::to_string(c));
  engine::EsammeOptions o;
  o.base.clear();
  for (int depth : {1, 3}) {
    engine::BaseSetting tree;
    tree.kind = engine::BaseKind::kDTree;
    tree.tree_max_depth = depth;
    o.base.push_back(tree);
  }
  o.update = engine::WeightUpdate::kSklearn;
  o.rounds = 50;
  const engine::EsammeModel model = engine::TrainEsamme(data, o);
  const std::vector<engine::FeatureMatrix> one = {x.topRows(1)};
  for (auto _ : state) benchmark::DoNotOptimize(engine::PredictEsamme(model, one));
  state.counters["rounds"] = static_cast<double>(model.rounds.size());
}
BENCHMARK(BM_PredictPerSample)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
