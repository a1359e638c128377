// OctoMap benchmark (SPEC section 7; issue 14 acceptance 5), figures printed beside the peer measured in the same run:
//   1. inserting one 640x480 rendered keyframe (back-projected, ray cast from the camera) through our path
//      (engine::OccupancyTree::InsertCloud, with its per-voxel stamps) vs raw liboctomap OcTree::insertPointCloud
//      on the same points, into trees that already hold the previous keyframes (as a robot's tree does);
//   2. the same through the service (decode the cached tree, insert, serialise .ot + stamps, zstd, SQLite commit),
//      as a client's cloud (stored at once) and as the keyframe feed (stored once per octomap_keyframes_per_commit);
//   3. point-query and ray-cast latency; .bt / .ot / stored sizes;
//   4. the height-band projection of a 20 x 20 m map (400 x 400 cells).
// Usage: anchordb_octomap_bench [--frames N]
#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <string>

#include "engine/octomap/height_bands.h"
#include "engine/octomap/occupancy_tree.h"
#include "engine/scene/projection.h"
#include "services/grid/grid_service.h"
#include "services/octomap/octomap_service.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "tests/support/temp_dir.h"

namespace {

using namespace anchordb;
using Steady = std::chrono::steady_clock;

double Ms(Steady::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

struct Stats {
  std::vector<double> ms;
  double mean() const { return std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size()); }
  double worst() const { return *std::max_element(ms.begin(), ms.end()); }
};

struct Keyframe {
  std::vector<Eigen::Vector3f> points_map;
  Eigen::Vector3d origin_map;
};

std::vector<Keyframe> RenderKeyframes(int n) {
  const sim::Scene scene = sim::MakeSetting(sim::Setting::kTA, 1).scene;
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  std::vector<Keyframe> out;
  for (int i = 0; i < n; ++i) {
    const double yaw = 2 * M_PI * i / n;
    const Eigen::Vector3d eye(0.2, -0.1, 1.3);
    const Eigen::Isometry3d X_WC = sim::LookAt(eye, eye + Eigen::Vector3d(2 * std::cos(yaw), 2 * std::sin(yaw), -1.0));
    const sim::Frame frame = sim::Render(scene, K, X_WC, sim::SensorModel{}, 7 + i);
    out.push_back({engine::BackProjectRaw(frame.depth_mm, 1000.0, K, X_WC), eye});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 12;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--frames") == 0) frames = std::max(1, std::atoi(argv[i + 1]));
  }
  const double max_range_m = 5.0;
  const std::vector<Keyframe> keyframes = RenderKeyframes(frames);
  std::size_t points = 0;
  for (const Keyframe& k : keyframes) points += k.points_map.size();
  std::printf("octomap bench: %d rendered 640x480 keyframes of the TA room (Kinect-like sensor), %.0f points each on "
              "average, resolution 0.05 m, max range %.1f m\n", frames, static_cast<double>(points) / frames, max_range_m);

  // 1. ours vs raw, alternating per frame so both see the same machine state.
  engine::OccupancyTree ours;
  octomap::OcTree raw(0.05);
  raw.setProbHit(0.7);
  raw.setProbMiss(0.4);
  raw.setClampingThresMin(0.12);
  raw.setClampingThresMax(0.97);
  Stats ours_ms, raw_ms;
  for (const Keyframe& k : keyframes) {
    octomap::Pointcloud cloud;
    cloud.reserve(k.points_map.size());
    auto t0 = Steady::now();
    for (const Eigen::Vector3f& p : k.points_map) cloud.push_back(p.x(), p.y(), p.z());
    raw.insertPointCloud(cloud, octomap::point3d(static_cast<float>(k.origin_map.x()), static_cast<float>(k.origin_map.y()),
                                                 static_cast<float>(k.origin_map.z())), max_range_m);
    raw_ms.ms.push_back(Ms(Steady::now() - t0));
    t0 = Steady::now();
    ours.InsertCloud(k.points_map, k.origin_map, max_range_m, 1);
    ours_ms.ms.push_back(Ms(Steady::now() - t0));
  }
  std::printf("insert one keyframe: ours %.1f ms mean, %.1f ms worst | raw OcTree::insertPointCloud %.1f ms mean, "
              "%.1f ms worst | ours / raw = %.3f (mean), %.3f (worst)\n",
              ours_ms.mean(), ours_ms.worst(), raw_ms.mean(), raw_ms.worst(), ours_ms.mean() / raw_ms.mean(),
              ours_ms.worst() / raw_ms.worst());
  std::printf("  same tree: %s (%zu leaves ours, %zu raw)\n",
              ours.Metadata().leaves == raw.getNumLeafNodes() ? "yes" : "NO", ours.Metadata().leaves,
              raw.getNumLeafNodes());

  // 2. through the service and its SQLite store.
  {
    testing::TempDir dir;
    storage::StoreOptions so;
    so.path = dir.File("bench.sqlite");
    storage::Store store(so);
    services::GridService grid(store, {}, {});
    services::OctomapService service(store, {}, SystemClock::Instance(), &grid);
    grid.CreateMap({"home", "home"});
    Stats service_ms;
    for (const Keyframe& k : keyframes) {
      const auto t0 = Steady::now();
      service.InsertPoints("home", k.points_map, k.origin_map, max_range_m, 1);
      service_ms.ms.push_back(Ms(Steady::now() - t0));
    }
    const services::OctomapInfo info = service.Get("home");
    std::printf("insert one keyframe through the service (insert + .ot + stamps + zstd + SQLite commit): %.1f ms mean, "
                "%.1f ms worst (%.2fx raw); tree %zu leaves, %zu stamped voxels, %lld bytes stored\n",
                service_ms.mean(), service_ms.worst(), service_ms.mean() / raw_ms.mean(), info.metadata.leaves,
                info.metadata.stamped_voxels, static_cast<long long>(info.stored_bytes));
  }

  // 2b. the keyframe feed's path (octomap_from_keyframes): the same keyframes integrated one at a time as the feed
  //     does after each stored keyframe, the tree stored once per octomap_keyframes_per_commit (default) keyframes.
  {
    testing::TempDir dir;
    storage::StoreOptions so;
    so.path = dir.File("bench.sqlite");
    storage::Store store(so);
    services::GridService grid(store, {}, {});
    services::OctomapSettings settings;
    services::OctomapService service(store, settings, SystemClock::Instance(), &grid);
    grid.CreateMap({"home", "home"});
    service.Configure("home", {});  // the tree exists, as it does after a map's first keyframe
    // Alternating with a raw tree of its own per keyframe, as in 1, so that both see the same machine state.
    octomap::OcTree raw_peer(0.05);
    raw_peer.setProbHit(0.7);
    raw_peer.setProbMiss(0.4);
    raw_peer.setClampingThresMin(0.12);
    raw_peer.setClampingThresMax(0.97);
    Stats feed_ms, peer_ms;
    std::int64_t id = 0;
    for (const Keyframe& k : keyframes) {
      octomap::Pointcloud cloud;
      cloud.reserve(k.points_map.size());
      auto t0 = Steady::now();
      for (const Eigen::Vector3f& p : k.points_map) cloud.push_back(p.x(), p.y(), p.z());
      raw_peer.insertPointCloud(cloud, octomap::point3d(static_cast<float>(k.origin_map.x()), static_cast<float>(k.origin_map.y()),
                                                        static_cast<float>(k.origin_map.z())), max_range_m);
      peer_ms.ms.push_back(Ms(Steady::now() - t0));
      services::KeyframeInTree in_tree{++id, k.points_map, k.origin_map, 1};
      t0 = Steady::now();
      service.IntegrateKeyframes("home", {in_tree});
      feed_ms.ms.push_back(Ms(Steady::now() - t0));
    }
    const auto t0 = Steady::now();
    service.CommitPending();
    const double last_commit_ms = Ms(Steady::now() - t0);
    const double amortised = (std::accumulate(feed_ms.ms.begin(), feed_ms.ms.end(), 0.0) + last_commit_ms) /
                             static_cast<double>(feed_ms.ms.size());
    std::printf("integrate one keyframe through the keyframe feed (one commit per %d keyframes, and the last at the "
                "end): %.1f ms amortised, %.1f ms worst (a commit) | raw alongside %.1f ms mean | amortised / raw = "
                "%.3f\n", settings.keyframes_per_commit, amortised, feed_ms.worst(), peer_ms.mean(),
                amortised / peer_ms.mean());
  }

  // 3. queries and sizes.
  {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> x(-3, 3), y(-2.5, 2.5), z(0, 2.5);
    std::vector<Eigen::Vector3d> q(10000);
    for (auto& p : q) p = {x(rng), y(rng), z(rng)};
    auto t0 = Steady::now();
    const auto answers = ours.Query(q);
    const double query_us = Ms(Steady::now() - t0) * 1000 / static_cast<double>(q.size());
    std::size_t known = 0;
    for (const auto& a : answers) known += a.state != engine::VoxelState::kUnknown;
    t0 = Steady::now();
    int hits = 0;
    for (int i = 0; i < 1000; ++i) {
      const double yaw = 2 * M_PI * i / 1000;
      hits += ours.CastRay({0.2, -0.1, 1.3}, {std::cos(yaw), std::sin(yaw), -0.3}, 8.0, true).stopped_by ==
              engine::VoxelState::kOccupied;
    }
    const double ray_us = Ms(Steady::now() - t0);
    const engine::TreeMetadata m = ours.Metadata();
    std::printf("point query %.2f us per point (10000 points, %zu known) | ray cast %.1f us per ray (1000 rays, %d hits)\n",
                query_us, known, ray_us, hits);
    std::printf("sizes: %zu nodes, %zu leaves, .bt %zu B, .ot %zu B, %zu B in memory (liboctomap)\n", m.nodes, m.leaves,
                ours.WriteBt().size(), ours.WriteOt().size(), m.memory_bytes);
  }

  // 4. projection of a 20 x 20 m map: clouds of a floor-level maze of pillars from origins on a 5 m lattice.
  {
    engine::OccupancyTree big;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f), h(0.0f, 2.0f);
    for (int ox = 0; ox < 4; ++ox) {
      for (int oy = 0; oy < 4; ++oy) {
        const Eigen::Vector3d origin(-7.5 + 5 * ox, -7.5 + 5 * oy, 1.0);
        std::vector<Eigen::Vector3f> cloud;
        for (int i = 0; i < 60000; ++i) {
          // the floor around the origin and pillar faces on a 1 m lattice
          cloud.emplace_back(static_cast<float>(origin.x()) + u(rng), static_cast<float>(origin.y()) + u(rng), 0.0f);
          const float px = std::round(static_cast<float>(origin.x()) + u(rng)) + 0.1f;
          cloud.emplace_back(px, std::round(static_cast<float>(origin.y()) + u(rng)) + 0.1f * u(rng) / 2.5f, h(rng));
        }
        big.InsertCloud(cloud, origin, 8.0, 1);
      }
    }
    const engine::TreeMetadata m = big.Metadata();
    GridGeometry g;
    g.width_cells = g.height_cells = 400;
    g.resolution_m = 0.05;
    g.origin_x_m = g.origin_y_m = -10;
    Stats projection;
    engine::BandCounts counts;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = Steady::now();
      const auto voxels = big.KnownVoxels({{-10, -10, 0.05}, {10, 10, 0.3}});
      const engine::BandCells cells = engine::ProjectBand(voxels, 0.0f, g, {"base", 0.05, 0.3});
      projection.ms.push_back(Ms(Steady::now() - t0));
      counts = engine::CountBand(cells);
    }
    std::printf("projection of a 20 x 20 m map (400 x 400 cells, band 0.05-0.3 m, tree of %zu leaves): %.1f ms mean, "
                "%.1f ms worst (%zu occupied, %zu free, %zu unknown cells)\n",
                m.leaves, projection.mean(), projection.worst(), counts.occupied, counts.free, counts.unknown);
  }
  return 0;
}
