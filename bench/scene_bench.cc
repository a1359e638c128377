// Scene-model benchmarks (SPEC section 7): Algorithm 1 per 640x480 frame beside OpenCV's MOG2 background
// subtractor on the same rendered frames, the noise cleaning, keyframe compression, and the whole per-frame update
// of the service (decode, Algorithm 1, the frame journal's commit) with the journal on and off.
#include <benchmark/benchmark.h>

#include <filesystem>

#include <opencv2/video/background_segm.hpp>

#include "engine/scene/depth_image.h"
#include "engine/scene/scene_model.h"
#include "services/scene/scene_service.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "storage/blob_codec.h"
#include "storage/repositories.h"

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

// What the journal adds on the CPU for a raw frame: the depth delta-shuffled and zstd-compressed (level 1).
void BM_JournalRawEncode_640x480(benchmark::State& state) {
  const auto& f = Frames().front();
  std::size_t stored = 0;
  for (auto _ : state) {
    stored = storage::EncodeBlob(storage::BlobElement::kU16, {480, 640}, storage::AsBytes(f.depth_mm), 1,
                                 storage::BlobFilter::kDeltaShuffle16).size();
  }
  state.counters["ratio"] = static_cast<double>(stored) / (640.0 * 480 * 2);
}
BENCHMARK(BM_JournalRawEncode_640x480)->Unit(benchmark::kMillisecond);

// The scene-model update per frame as the server runs it, without HTTP: SceneService::AddFrame on a real SQLite file
// (WAL, synchronous=FULL: a commit is an fsync) fed the 10 frames before the object moves (no keyframe after the
// first), as PNG or raw. Args: journal (0 off: a checkpoint every 30 frames only; 1 on: every frame committed), png.
void BM_SceneServiceFrame_640x480(benchmark::State& state) {
  const bool journal = state.range(0) != 0, png = state.range(1) != 0;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("anchordb-scene-bench-" + std::to_string(state.range(0)) + std::to_string(state.range(1)));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    storage::StoreOptions so;
    so.path = (dir / "bench.sqlite").string();
    storage::Store store(so);
    store.Write([](storage::Connection& c) { storage::InsertMap(c, {"bench", "bench", 0}); });
    services::SceneLimits limits;
    limits.frame_journal = journal;
    services::SceneService scenes(store, limits);
    services::OpenSceneRequest open;
    open.camera = sim::KinectIntrinsics();
    open.merge = false;
    const std::int64_t id = scenes.Open("bench", open).id;
    std::vector<std::string> bodies;
    for (int i = 0; i < 10; ++i) {
      const auto& f = Frames()[i];
      bodies.push_back(png ? engine::EncodeDepthPng(f.depth_mm, 640, 480) : std::string(storage::AsBytes(f.depth_mm)));
    }
    std::size_t i = 0;
    for (auto _ : state) {
      services::FrameInput in;
      in.png = png;
      in.body = bodies[i++ % bodies.size()];
      benchmark::DoNotOptimize(scenes.AddFrame("bench", id, in).frames);
    }
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_SceneServiceFrame_640x480)->UseRealTime()->ArgNames({"journal", "png"})->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
