// Real Kinect views (slambook2 ch5: a furnished room, 5 views with poses T_world_camera, depth in mm) enter as
// scene models with their poses through the scene service and its SQLite store; the back-projected static layers
// of overlapping views must agree in the map frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <unordered_map>

#include "services/grid/grid_service.h"
#include "services/scene/scene_service.h"
#include "engine/scene/depth_image.h"
#include "engine/scene/projection.h"
#include "tests/support/real_data_files.h"
#include "tests/support/temp_dir.h"

namespace anchordb {
namespace {

std::string DataDir() {
  const char* env = std::getenv("ANCHORDB_SHARED_DATA");
  return std::string(env ? env : "../shared/data") + "/slambook2_rgbd/ch5/rgbd";
}

using testing::ReadFile;
using testing::ReadPgm16;

double MedianNearestNeighbour(const std::vector<Eigen::Vector3f>& reference, const std::vector<Eigen::Vector3f>& query,
                              double cell_m) {
  auto key = [cell_m](const Eigen::Vector3f& p, int dx, int dy, int dz) {
    const auto ix = static_cast<std::int64_t>(std::floor(p.x() / cell_m)) + dx;
    const auto iy = static_cast<std::int64_t>(std::floor(p.y() / cell_m)) + dy;
    const auto iz = static_cast<std::int64_t>(std::floor(p.z() / cell_m)) + dz;
    return (ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791);
  };
  std::unordered_multimap<std::int64_t, std::size_t> grid;
  for (std::size_t i = 0; i < reference.size(); ++i) grid.emplace(key(reference[i], 0, 0, 0), i);
  std::vector<double> d;
  for (std::size_t q = 0; q < query.size(); q += 7) {
    double best = cell_m * 2;  // farther than the searched neighbourhood: counted as 2 cells
    for (int dx = -1; dx <= 1; ++dx) for (int dy = -1; dy <= 1; ++dy) for (int dz = -1; dz <= 1; ++dz) {
      auto [a, b] = grid.equal_range(key(query[q], dx, dy, dz));
      for (auto it = a; it != b; ++it) best = std::min(best, static_cast<double>((reference[it->second] - query[q]).norm()));
    }
    d.push_back(best);
  }
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

// One real view: its pose (T_world_camera from pose.txt) and its depth as raw little-endian bytes.
struct RealView {
  Pose3 pose;
  std::string raw_depth;
};

std::vector<RealView> ReadViews() {
  std::ifstream poses(DataDir() + "/pose.txt");
  if (!poses) throw std::runtime_error("missing " + DataDir() + "/pose.txt");
  std::vector<RealView> views;
  for (int view = 1; view <= 5; ++view) {
    double t[3], q[4];
    poses >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3];
    RealView v;
    v.pose.position_m = {t[0], t[1], t[2]};
    v.pose.orientation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized();
    int w = 0, h = 0;
    const auto depth = ReadPgm16(DataDir() + "/depth/" + std::to_string(view) + ".pgm", w, h);
    if (w != 640 || h != 480) throw std::runtime_error("view " + std::to_string(view) + " is not 640x480");
    v.raw_depth.assign(reinterpret_cast<const char*>(depth.data()), depth.size() * 2);
    views.push_back(std::move(v));
  }
  return views;
}

// A scene service on a fresh SQLite file with the map "room".
class RealRoom {
 public:
  explicit RealRoom(const std::string& file) : store_(Options(dir_.File(file))), grid_(store_, {}, {}), scenes(store_, {}) {
    grid_.CreateMap({"room", "slambook ch5 room"});
  }
  // Opens a scene model at the view's pose (fx 518, fy 519) and feeds it the view's depth three times.
  std::int64_t Observe(const RealView& v) {
    services::OpenSceneRequest request;
    request.camera = kK;
    request.X_MapCamera = v.pose;
    const std::int64_t id = scenes.Open("room", request).id;
    for (int frame = 0; frame < 3; ++frame) {
      services::FrameInput in;
      in.body = v.raw_depth;
      in.png = false;
      scenes.AddFrame("room", id, in);
    }
    return id;
  }
  static constexpr PinholeIntrinsics kK{640, 480, 518.0, 519.0, 325.5, 253.5};

 private:
  static storage::StoreOptions Options(const std::string& path) {
    storage::StoreOptions so;
    so.path = path;
    return so;
  }
  testing::TempDir dir_;
  storage::Store store_;
  services::GridService grid_;

 public:
  services::SceneService scenes;
};

TEST(SlambookRealData, StaticLayersOfViews4And5AgreeInTheMapFrame) {
  RealRoom room("real.sqlite");
  services::SceneService& scenes = room.scenes;
  const PinholeIntrinsics K = RealRoom::kK;
  std::vector<std::int64_t> ids;
  std::vector<Eigen::Isometry3d> X_MapCamera;
  for (const RealView& v : ReadViews()) {
    ids.push_back(room.Observe(v));
    X_MapCamera.push_back(engine::ToIsometry(v.pose));
    scenes.Close("room", ids.back());
  }
  // Read the static layers back (as a client would: raw f32 metres) and back-project them.
  auto cloud = [&](int view) {
    const auto layer = scenes.Layer("room", ids[view - 1], services::SceneLayerKind::kStatic, services::SceneLayerEncoding::kRaw, false);
    std::vector<float> metres(layer.body.size() / 4);
    std::memcpy(metres.data(), layer.body.data(), layer.body.size());
    for (float& m : metres) m = m > 7.0f ? 0.0f : m;  // the far, sparse range of the Kinect is noise
    return engine::BackProject(metres, K, X_MapCamera[view - 1]);
  };
  const auto c4 = cloud(4), c5 = cloud(5);
  ASSERT_GT(c4.size(), 100000u);
  ASSERT_GT(c5.size(), 100000u);
  const double with_poses = MedianNearestNeighbour(c4, c5, 0.1);
  EXPECT_LT(with_poses, 0.05);
  // The poses matter: the same clouds without them (both in their camera frames) agree much worse.
  std::vector<Eigen::Vector3f> c5_in_camera;
  const Eigen::Isometry3f X_inv = X_MapCamera[4].inverse().cast<float>();
  const Eigen::Isometry3f X_4 = X_MapCamera[3].cast<float>();
  for (const auto& p : c5) c5_in_camera.push_back(X_4 * (X_inv * p));  // pretend view 5 sat where view 4 was
  EXPECT_GT(MedianNearestNeighbour(c4, c5_in_camera, 0.1), with_poses);
  RecordProperty("median_nn_m", std::to_string(with_poses));
  std::printf("median nearest-neighbour distance view 5 -> view 4: %.4f m\n", with_poses);
}

// Issue 4, acceptance 4: nothing moved between the five real views, so merging each into the next must not invent
// movable structure: after cleaning, under 2 % of the pixels are movable in every merged model.
TEST(SlambookRealData, MergedRealViewsHaveFewMovablePixels) {
  RealRoom room("merge.sqlite");
  services::SceneService& scenes = room.scenes;
  int merged_models = 0;
  int view = 0;
  for (const RealView& v : ReadViews()) {
    ++view;
    const std::int64_t id = room.Observe(v);
    const services::SceneInfo scene = scenes.Get("room", id);
    const double fraction = scenes.LayerSummary("room", id, services::SceneLayerKind::kMovable, true).fraction;
    const auto used = scene.merge.models_used.size();
    merged_models += static_cast<int>(used);
    std::printf("view %d: merged %zu earlier model(s), cleaned movable fraction %.4f\n", view, used, fraction);
    // Issue 4's bar. Measured: 0.00, 0.00, 0.55, 1.14 and 1.81 % for views 1-5 (view 5 merges four earlier models);
    // with issue 13's registration and premises 0.00, 0.00, 0.38, 1.04 and 1.18 %.
    EXPECT_LT(fraction, 0.02) << "merged " << used << " model(s), performed " << scene.merge.performed;
    scenes.Close("room", id);
  }
  EXPECT_GE(merged_models, 4);  // every view after the first merged at least one earlier one
}

// Issue 13, acceptance 3: the same five views with every stored pose off by exactly 3 cm and 2 deg (a random
// direction and axis per view, 10 seeded draws), as AMCL-class localisation has it: under 2 % movable after cleaning
// in every merged model, whatever the registration makes of it (corrects it, or the merge falls back).
TEST(SlambookRealData, MergedRealViewsWithPerturbedPosesHaveFewMovablePixels) {
  const std::vector<RealView> views = ReadViews();
  double worst = 0.0;
  int fallbacks = 0, models = 0;
  for (std::uint64_t draw = 1; draw <= 10; ++draw) {
    std::mt19937_64 rng(draw * 7919);
    const auto uniform = [&](double lo, double hi) {
      return lo + (hi - lo) * static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
    };
    const auto unit = [&] {
      const double z = uniform(-1, 1), phi = uniform(0, 2 * std::numbers::pi), r = std::sqrt(1 - z * z);
      return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
    };
    RealRoom room("perturbed" + std::to_string(draw) + ".sqlite");
    services::SceneService& scenes = room.scenes;
    int view = 0;
    for (RealView v : views) {
      ++view;
      v.pose.position_m += unit() * 0.03;
      v.pose.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * std::numbers::pi / 180.0, unit())) *
                            v.pose.orientation).normalized();
      const std::int64_t id = room.Observe(v);
      const services::SceneInfo scene = scenes.Get("room", id);
      const double fraction = scenes.LayerSummary("room", id, services::SceneLayerKind::kMovable, true).fraction;
      for (const auto& m : scene.merge.models_used) fallbacks += !m.icp_applied, ++models;
      worst = std::max(worst, fraction);
      EXPECT_LT(fraction, 0.02) << "draw " << draw << " view " << view << ": merged "
                                << scene.merge.models_used.size() << " model(s)";
      scenes.Close("room", id);
    }
  }
  // Measured: worst 1.48 % (22 of 100 merged models without an applied correction).
  std::printf("perturbed 3 cm / 2 deg, 10 draws: worst cleaned movable fraction %.4f; %d of %d merged models without "
              "an applied correction\n", worst, fallbacks, models);
  RecordProperty("worst_fraction", std::to_string(worst));
}

}  // namespace
}  // namespace anchordb
