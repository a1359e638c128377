// Benchmarks of the grid engine and the blob codec (SPEC section 7: figures, never timed unit tests).
//   - observation update of a 400x400 probability layer (goal: <= 2 ms), a 1.0 rad / 3.5 m field of view and a
//     360 degree / 10 m variant that sees the whole grid;
//   - region extraction on a 400x400 probability grid with a few dozen blobs;
//   - viewpoint planning on the real AWS small-house map, around the kitchen table with a person beside it;
//   - zstd blob encode/decode of a 400x400 float layer.
// All inputs are generated from fixed seeds, so every run measures the same work.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/grid/grid.h"
#include "engine/grid/log_odds.h"
#include "engine/grid/map_server.h"
#include "engine/grid/observation.h"
#include "engine/grid/raster.h"
#include "engine/grid/regions.h"
#include "engine/grid/viewpoints.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::bench {
namespace {

using engine::LogOddsGrid;
using engine::MaskGrid;
using engine::OccupancyGrid;
using engine::ProbabilityGrid;

constexpr int kCells = 400;          // 400 x 400 cells
constexpr double kResolution = 0.05;  // 20 m x 20 m

GridGeometry Geometry400() {
  GridGeometry g;
  g.width_cells = kCells;
  g.height_cells = kCells;
  g.resolution_m = kResolution;
  g.origin_x_m = 0.0;
  g.origin_y_m = 0.0;
  return g;
}

void FillBox(OccupancyGrid& grid, int x0, int y0, int x1, int y1, std::int8_t value) {
  for (int iy = std::max(0, y0); iy <= std::min(grid.geometry.height_cells - 1, y1); ++iy) {
    for (int ix = std::max(0, x0); ix <= std::min(grid.geometry.width_cells - 1, x1); ++ix) grid.at(ix, iy) = value;
  }
}

// A 20 m x 20 m flat: free floor, outer walls, interior walls with door gaps, a strip of unknown cells and
// furniture-sized boxes at fixed-seed random places (kept clear of the sensor positions used below).
OccupancyGrid MakeApartment() {
  OccupancyGrid grid(Geometry400(), 0);
  const std::int8_t wall = 100;
  FillBox(grid, 0, 0, kCells - 1, 2, wall);
  FillBox(grid, 0, kCells - 3, kCells - 1, kCells - 1, wall);
  FillBox(grid, 0, 0, 2, kCells - 1, wall);
  FillBox(grid, kCells - 3, 0, kCells - 1, kCells - 1, wall);
  // Interior walls (3 cells = 15 cm thick) with 1 m door gaps.
  FillBox(grid, 130, 0, 132, 170, wall);
  FillBox(grid, 130, 190, 132, 399, wall);
  FillBox(grid, 270, 0, 272, 80, wall);
  FillBox(grid, 270, 100, 272, 399, wall);
  FillBox(grid, 0, 250, 60, 252, wall);
  FillBox(grid, 80, 250, 130, 252, wall);
  FillBox(grid, 272, 200, 330, 202, wall);
  FillBox(grid, 350, 200, 399, 202, wall);
  // A strip the SLAM never saw.
  FillBox(grid, 5, 5, 40, 60, -1);
  std::mt19937 rng(20240601u);
  std::uniform_int_distribution<int> pos(10, kCells - 30);
  std::uniform_int_distribution<int> size(6, 20);
  for (int i = 0; i < 24; ++i) {
    const int x = pos(rng), y = pos(rng), w = size(rng), h = size(rng);
    if (std::abs(x + w / 2 - 200) < 30 && std::abs(y + h / 2 - 200) < 30) continue;  // keep the centre clear
    FillBox(grid, x, y, x + w, y + h, wall);
  }
  return grid;
}

Polygon2 Rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// Sensor poses in the free middle room, each looking at a different direction, with a table-sized stimulus
// 1.5 m ahead. Cycling through them keeps the benchmark from measuring one lucky pose.
std::vector<engine::Observation> ObservationSet(double fov_rad, double range_m) {
  std::vector<engine::Observation> set;
  for (int k = 0; k < 8; ++k) {
    engine::Observation o;
    const double heading = k * std::numbers::pi / 4.0 + 0.1;
    o.sensor_position_m = Eigen::Vector2d(10.0 + 0.3 * std::cos(k), 10.0 + 0.3 * std::sin(k));
    o.heading_rad = heading;
    o.fov_rad = fov_rad;
    o.range_m = range_m;
    const Eigen::Vector2d c = o.sensor_position_m + 1.5 * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    o.stimulus_map.push_back(Rectangle(c.x() - 0.4, c.y() - 0.3, c.x() + 0.4, c.y() + 0.3));
    set.push_back(std::move(o));
  }
  return set;
}

void RunObservation(benchmark::State& state, double fov_rad, double range_m) {
  const OccupancyGrid occupancy = MakeApartment();
  const engine::OccupancyThresholds thresholds;
  const engine::LogOddsModel model{LogOddsParams{}};
  const auto observations = ObservationSet(fov_rad, range_m);
  LogOddsGrid log_odds(occupancy.geometry, 0.0f);
  std::size_t i = 0;
  std::size_t cells_in_view = 0, raised = 0, lowered = 0, blocked = 0;
  for (auto _ : state) {
    const auto counts = engine::ApplyObservation(occupancy, thresholds, model, observations[i % observations.size()],
                                                 log_odds);
    benchmark::DoNotOptimize(log_odds.cells.data());
    cells_in_view += counts.raised + counts.lowered + counts.unchanged_blocked;
    raised += counts.raised;
    lowered += counts.lowered;
    blocked += counts.unchanged_blocked;
    ++i;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["cells_in_view"] = static_cast<double>(cells_in_view) / n;
  state.counters["raised"] = static_cast<double>(raised) / n;
  state.counters["lowered"] = static_cast<double>(lowered) / n;
  state.counters["blocked"] = static_cast<double>(blocked) / n;
  state.SetItemsProcessed(static_cast<std::int64_t>(cells_in_view));
  state.SetLabel("400x400 @ 0.05 m");
}

void BM_ObservationUpdate_Fov1rad_3p5m(benchmark::State& state) { RunObservation(state, 1.0, 3.5); }
void BM_ObservationUpdate_360deg_10m(benchmark::State& state) { RunObservation(state, 2.0 * std::numbers::pi, 10.0); }

// A probability grid with low-probability noise and `blobs` blobs (ellipses and rectangles) above 0.5.
ProbabilityGrid MakeBlobGrid(int blobs) {
  ProbabilityGrid grid(Geometry400(), 0.0f);
  std::mt19937 rng(7u);
  std::uniform_real_distribution<float> background(0.05f, 0.45f);
  for (float& p : grid.cells) p = background(rng);
  std::uniform_real_distribution<double> centre(20.0, kCells - 20.0);
  std::uniform_real_distribution<double> radius(3.0, 15.0);
  std::uniform_real_distribution<float> high(0.55f, 0.97f);
  for (int b = 0; b < blobs; ++b) {
    const double cx = centre(rng), cy = centre(rng), rx = radius(rng), ry = radius(rng);
    const bool ellipse = b % 3 != 0;
    for (int iy = static_cast<int>(cy - ry); iy <= static_cast<int>(cy + ry); ++iy) {
      for (int ix = static_cast<int>(cx - rx); ix <= static_cast<int>(cx + rx); ++ix) {
        if (!grid.geometry.Contains(ix, iy)) continue;
        const double u = (ix + 0.5 - cx) / rx, v = (iy + 0.5 - cy) / ry;
        if (ellipse && u * u + v * v > 1.0) continue;
        grid.at(ix, iy) = high(rng);
      }
    }
  }
  return grid;
}

void BM_ExtractRegions_36blobs(benchmark::State& state) {
  const ProbabilityGrid grid = MakeBlobGrid(36);
  std::size_t regions = 0;
  for (auto _ : state) {
    auto r = engine::ExtractRegions(grid, 0.5, 0.02);
    regions = r.size();
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["regions"] = static_cast<double>(regions);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(grid.cells.size()));
  state.SetLabel("400x400, threshold 0.5");
}

// ---- viewpoints on the AWS RoboMaker small house (real map_server data)

std::string SharedDataDir() {
  if (const char* env = std::getenv("ANCHORDB_SHARED_DATA"); env && *env) return env;
  return std::string(ANCHORDB_SOURCE_DIR) + "/../shared/data";
}

bool ReadFile(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

void BM_PlanViewpoints_AwsKitchenTable(benchmark::State& state) {
  const std::string dir = SharedDataDir() + "/aws_small_house/maps/turtlebot3_waffle_pi";
  std::string yaml, image;
  if (!ReadFile(dir + "/map.yaml", yaml) || !ReadFile(dir + "/map.pgm", image)) {
    state.SkipWithError(("AWS map not found: " + dir + "/map.{yaml,pgm} (set ANCHORDB_SHARED_DATA to the folder "
                         "holding aws_small_house/)").c_str());
    return;
  }
  OccupancyGrid occupancy;
  try {
    const auto parsed = engine::ParseMapServerYaml(yaml);
    const auto grey = engine::DecodeMapImage(image, 4096u * 4096u);
    occupancy = engine::ToOccupancy(grey, parsed.meta);
  } catch (const std::exception& e) {
    state.SkipWithError((std::string("cannot decode the AWS map: ") + e.what()).c_str());
    return;
  }
  // KitchenTable_01_001 in worlds/small_house_model_poses.csv stands at (6.553, 0.951) with yaw -1.564; its model
  // is 0.70 m x 1.80 m, so in the map frame the top spans about 1.8 m along x and 0.7 m along y.
  MaskGrid surface(occupancy.geometry, 0);
  engine::RasterisePolygons({Rectangle(6.553 - 0.9, 0.951 - 0.35, 6.553 + 0.9, 0.951 + 0.35)}, surface);
  Agent person;
  person.id = "person";
  person.position_m = Eigen::Vector2d(5.25, 0.95);  // at the table's west end, facing it
  person.heading_rad = 0.0;
  const Eigen::Vector2d robot(2.0, 0.0);
  const engine::ViewpointOptions options;
  engine::ViewpointPlan plan;
  try {  // once outside the timed loop, so a failure is reported instead of escaping the loop
    plan = engine::PlanViewpoints(occupancy, surface, robot, person, options);
  } catch (const std::exception& e) {
    state.SkipWithError((std::string("PlanViewpoints failed: ") + e.what()).c_str());
    return;
  }
  for (auto _ : state) {
    plan = engine::PlanViewpoints(occupancy, surface, robot, person, options);
    benchmark::DoNotOptimize(plan.viewpoints.data());
  }
  state.counters["viewpoints"] = static_cast<double>(plan.viewpoints.size());
  state.counters["boundary_cells"] = static_cast<double>(plan.boundary_cells);
  state.counters["candidates"] = static_cast<double>(plan.candidate_cells);
  state.counters["clusters"] = plan.clusters;
  std::string label = std::to_string(occupancy.geometry.width_cells) + "x" +
                      std::to_string(occupancy.geometry.height_cells) + " AWS small house";
  if (!plan.viewpoints.empty()) {
    const auto& best = plan.viewpoints.front();
    char text[96];
    std::snprintf(text, sizeof(text), "; best (%.2f, %.2f) %s score %.2f", best.position_m.x(), best.position_m.y(),
                  best.relation.c_str(), best.score);
    label += text;
  }
  state.SetLabel(label);
}

// ---- blob codec of a 400x400 float layer

std::vector<float> RealisticLayer() {
  const OccupancyGrid occupancy = MakeApartment();
  const engine::LogOddsModel model{LogOddsParams{}};
  LogOddsGrid log_odds(occupancy.geometry, 0.0f);
  std::mt19937 rng(99u);
  std::uniform_real_distribution<double> xy(1.0, 19.0), angle(-std::numbers::pi, std::numbers::pi);
  for (int k = 0; k < 40; ++k) {
    engine::Observation o;
    o.sensor_position_m = Eigen::Vector2d(xy(rng), xy(rng));
    o.heading_rad = angle(rng);
    o.fov_rad = 1.0;
    o.range_m = 3.5;
    const Eigen::Vector2d c = o.sensor_position_m + 1.5 * Eigen::Vector2d(std::cos(o.heading_rad), std::sin(o.heading_rad));
    o.stimulus_map.push_back(Rectangle(c.x() - 0.4, c.y() - 0.3, c.x() + 0.4, c.y() + 0.3));
    engine::ApplyObservation(occupancy, {}, model, o, log_odds);
  }
  return log_odds.cells;
}

// Two layers: `sparse` is a log-odds layer after 40 observations (mostly 0, some clamped hits and misses), what
// the store writes after updates; `noisy` is the region benchmark's probability grid (a random float in every
// cell), close to zstd's worst case.
std::vector<float> BlobLayer(bool noisy) { return noisy ? MakeBlobGrid(36).cells : RealisticLayer(); }

void BM_BlobEncode_400x400_f32(benchmark::State& state, bool noisy) {
  const std::vector<float> layer = BlobLayer(noisy);
  const std::string_view raw = storage::AsBytes(layer);
  std::size_t encoded_size = 0;
  for (auto _ : state) {
    const std::string blob = storage::EncodeBlob(storage::BlobElement::kF32, {kCells, kCells}, raw);
    encoded_size = blob.size();
    benchmark::DoNotOptimize(blob.data());
  }
  state.counters["raw_bytes"] = static_cast<double>(raw.size());
  state.counters["blob_bytes"] = static_cast<double>(encoded_size);
  state.counters["ratio"] = static_cast<double>(encoded_size) / static_cast<double>(raw.size());
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(raw.size()));
}

void BM_BlobDecode_400x400_f32(benchmark::State& state, bool noisy) {
  const std::vector<float> layer = BlobLayer(noisy);
  const std::string blob = storage::EncodeBlob(storage::BlobElement::kF32, {kCells, kCells}, storage::AsBytes(layer));
  for (auto _ : state) {
    storage::DecodedBlob decoded = storage::DecodeBlob(blob);
    benchmark::DoNotOptimize(decoded.bytes.data());
  }
  state.counters["blob_bytes"] = static_cast<double>(blob.size());
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(layer.size() * sizeof(float)));
}

BENCHMARK(BM_ObservationUpdate_Fov1rad_3p5m)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObservationUpdate_360deg_10m)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExtractRegions_36blobs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanViewpoints_AwsKitchenTable)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BlobEncode_400x400_f32, sparse, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BlobEncode_400x400_f32, noisy, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BlobDecode_400x400_f32, sparse, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BlobDecode_400x400_f32, noisy, true)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace anchordb::bench

BENCHMARK_MAIN();
