// Furniture segmentation (issue 16, SPEC section 7): segmentation time per room cloud — the furnished room of
// sim/apartment_furnished.h scanned from its six views (Kinect-like sensor, depth to 3.5 m, about 1.1 million
// points), at the default parameters and at a coarser voxel. Google Benchmark; --benchmark_format=json for JSON.
#include <benchmark/benchmark.h>

#include "engine/scene/projection.h"
#include "engine/segmentation/furniture_segmentation.h"
#include "sim/apartment.h"
#include "sim/apartment_furnished.h"

namespace {

using namespace anchordb;

const std::vector<Eigen::Vector3f>& RoomCloud() {
  static const std::vector<Eigen::Vector3f> cloud = [] {
    const sim::FurnishedRoom room = sim::MakeFurnishedRoom(1);
    const PinholeIntrinsics K = sim::KinectIntrinsics();
    std::vector<Eigen::Vector3f> out;
    for (std::size_t v = 0; v < room.X_WorldCamera.size(); ++v) {
      sim::Frame f = sim::Render(room.scene, K, room.X_WorldCamera[v], sim::SensorModel{}, 31 + v);
      for (auto& d : f.depth_mm) {
        if (d > 3500) d = 0;
      }
      const auto points = engine::BackProjectRaw(f.depth_mm, 1000.0, K, room.X_WorldCamera[v]);
      out.insert(out.end(), points.begin(), points.end());
    }
    return out;
  }();
  return cloud;
}

void BM_SegmentRoomCloud(benchmark::State& state, double voxel_m) {
  const auto& cloud = RoomCloud();
  engine::segmentation::SegmentationParams p;
  p.voxel_m = voxel_m;
  p.min_cluster_points = static_cast<std::size_t>(150.0 * (0.02 / voxel_m) * (0.02 / voxel_m));
  p.min_plane_points = static_cast<std::size_t>(400.0 * (0.02 / voxel_m) * (0.02 / voxel_m));
  std::size_t segments = 0;
  for (auto _ : state) {
    const auto r = engine::segmentation::SegmentFurniture(cloud, p);
    segments = r.segments.size();
    benchmark::DoNotOptimize(r.segments.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["segments"] = static_cast<double>(segments);
}
BENCHMARK_CAPTURE(BM_SegmentRoomCloud, voxel_2cm, 0.02)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_SegmentRoomCloud, voxel_4cm, 0.04)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
