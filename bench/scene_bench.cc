// Scene-model benchmarks (SPEC section 7): Algorithm 1 per 640x480 frame beside OpenCV's MOG2 background
// subtractor on the same rendered frames, the noise cleaning, and keyframe compression.
#include <benchmark/benchmark.h>

#include <opencv2/video/background_segm.hpp>

#include "engine/scene/scene_model.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "storage/blob_codec.h"

namespace {

using namespace anchordb;

// 20 rendered frames of the tabletop from viewpoint A; an object moves after frame 10.
const std::vector<sim::Frame>& Frames() {
  static const std::vector<sim::Frame> frames = [] {
    sim::SettingScene s = sim::MakeSetting(sim::Setting::kTA, 1);
    std::vector<sim::Frame> out;
    for (int i = 0; i < 20; ++i) {
      if (i == 10) {
        Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
        X.translation() = Eigen::Vector3d(0.15, 0.1, 0.0);
        sim::MoveObject(s.scene, s.movable_ids.at(1), X);
      }
      out.push_back(sim::Render(s.scene, sim::KinectIntrinsics(), s.X_WorldCameraA, sim::SensorModel{}, 100 + i));
    }
    return out;
  }();
  return frames;
}

void BM_AlgorithmOne_640x480(benchmark::State& state) {
  const auto& frames = Frames();
  engine::SceneModelState model = engine::NewSceneModel(640, 480);
  engine::SceneModelParams params;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto counts = engine::ApplyFrame(model, frames[i++ % frames.size()].depth_mm, 1000.0, {}, params);
    benchmark::DoNotOptimize(counts.movable);
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_AlgorithmOne_640x480)->Unit(benchmark::kMillisecond);

// The peer: OpenCV's Gaussian-mixture background subtractor on the same depth frames as 8-bit images
// (MOG2 takes 8-bit or float images; 8-bit is its usual and fastest input). Single-threaded like ours.
void BM_OpenCvMog2_640x480(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = Frames();
  std::vector<cv::Mat> images;
  for (const auto& f : frames) {
    cv::Mat m(480, 640, CV_16U, const_cast<std::uint16_t*>(f.depth_mm.data()));
    cv::Mat eight;
    m.convertTo(eight, CV_8U, 255.0 / 6000.0);
    images.push_back(eight);
  }
  auto mog2 = cv::createBackgroundSubtractorMOG2(500, 16.0, false);
  cv::Mat foreground;
  std::size_t i = 0;
  for (auto _ : state) {
    mog2->apply(images[i++ % images.size()], foreground);
    benchmark::DoNotOptimize(foreground.data);
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OpenCvMog2_640x480)->Unit(benchmark::kMillisecond);

void BM_CleanMovable_640x480(benchmark::State& state) {
  engine::SceneModelState model = engine::NewSceneModel(640, 480);
  for (const auto& f : Frames()) engine::ApplyFrame(model, f.depth_mm, 1000.0, {}, {});
  for (auto _ : state) benchmark::DoNotOptimize(engine::CleanMovable(model.movable, 640, 480).data());
}
BENCHMARK(BM_CleanMovable_640x480)->Unit(benchmark::kMillisecond);

// A keyframe: raw depth + background, both 16-bit mm, delta-shuffle + zstd. ratio = stored / raw.
void BM_KeyframeEncode_640x480(benchmark::State& state) {
  const auto& f = Frames().back();
  engine::SceneModelState model = engine::NewSceneModel(640, 480);
  for (const auto& frame : Frames()) engine::ApplyFrame(model, frame.depth_mm, 1000.0, {}, {});
  std::vector<std::uint16_t> background(model.background_m.size());
  for (std::size_t i = 0; i < background.size(); ++i) background[i] = static_cast<std::uint16_t>(model.background_m[i] * 1000.0f + 0.5f);
  std::size_t stored = 0;
  for (auto _ : state) {
    const std::string a = storage::EncodeBlob(storage::BlobElement::kU16, {480, 640}, storage::AsBytes(f.depth_mm), 3,
                                              storage::BlobFilter::kDeltaShuffle16);
    const std::string b = storage::EncodeBlob(storage::BlobElement::kU16, {480, 640}, storage::AsBytes(background), 3,
                                              storage::BlobFilter::kDeltaShuffle16);
    stored = a.size() + b.size();
  }
  const double raw = 2.0 * 640 * 480 * 2;
  state.counters["stored_bytes"] = static_cast<double>(stored);
  state.counters["ratio"] = static_cast<double>(stored) / raw;
  const std::string plain = storage::EncodeBlob(storage::BlobElement::kU16, {480, 640}, storage::AsBytes(f.depth_mm), 3);
  state.counters["depth_ratio_without_filter"] = static_cast<double>(plain.size()) / (raw / 2);
}
BENCHMARK(BM_KeyframeEncode_640x480)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
