// `anchordb import tum` on a short sequence written in TUM RGB-D's layout from rendered frames (sim/): the command's
// progress and summary, the scene models and keyframes it stores, the map's OctoMap occupied at the rendered
// surfaces and free before them (TUM poses are the optical frame in the world: a frame mix-up misplaces both), and
// clear errors with a non-zero exit that store nothing.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/scene/depth_image.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace anchordb {
namespace tum_import_http_test {

using nlohmann::json;

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

CommandResult RunAnchordb(const std::string& args) {
  const std::string bin = testing::AnchordbBin();
  CommandResult r;
  FILE* pipe = popen((std::string(bin) + " " + args + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0;) r.output.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// The benchmark's Freiburg 1 depth camera (the import's default).
PinholeIntrinsics Fr1() {
  PinholeIntrinsics k;
  k.fx = 517.3, k.fy = 516.5, k.cx = 318.6, k.cy = 255.3;
  return k;
}

constexpr double kFirstStamp_s = 1305031102.175304;
constexpr int kFrames = 4;

class TumImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    seq_ = dir_.File("rgbd_dataset_freiburg1_rendered");
    std::filesystem::create_directories(seq_ + "/depth");
    const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA);
    scene_ = setting.scene;
    sim::SensorModel exact;
    exact.noise = false;
    std::ofstream depth(seq_ + "/depth.txt"), rgb(seq_ + "/rgb.txt"), truth(seq_ + "/groundtruth.txt");
    depth << "# depth maps\n# file: 'rendered'\n# timestamp filename\n";
    rgb << "# color images\n# timestamp filename\n";
    truth << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
    const Eigen::Quaterniond qa(setting.X_WorldCameraA.rotation()), qb(setting.X_WorldCameraB.rotation());
    for (int k = 0; k < kFrames; ++k) {
      const double t = k / double(kFrames - 1);
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = qa.slerp(t, qb).toRotationMatrix();
      X.translation() = (1 - t) * setting.X_WorldCameraA.translation() + t * setting.X_WorldCameraB.translation();
      const sim::Frame f = sim::Render(scene_, Fr1(), X, exact, 7 + k);
      std::vector<std::uint16_t> tum(f.depth_mm.size());
      for (std::size_t i = 0; i < tum.size(); ++i) tum[i] = static_cast<std::uint16_t>(std::min(65535, f.depth_mm[i] * 5));
      char stamp[32], name[64];
      std::snprintf(stamp, sizeof(stamp), "%.6f", kFirstStamp_s + 0.2 * k);
      std::snprintf(name, sizeof(name), "depth/%.6f.png", kFirstStamp_s + 0.2 * k);
      std::ofstream(seq_ + "/" + name, std::ios::binary) << engine::EncodeDepthPng(tum, f.width, f.height);
      depth << stamp << " " << name << "\n";
      rgb << stamp << " rgb/" << stamp << ".png\n";
      const Eigen::Quaterniond q(X.rotation());
      truth.precision(6);
      truth << std::fixed << kFirstStamp_s + 0.2 * k + 0.004 << " " << X.translation().x() << " "
            << X.translation().y() << " " << X.translation().z() << " " << q.x() << " " << q.y() << " " << q.z()
            << " " << q.w() << "\n";
      frames_.push_back(f);
      poses_.push_back(X);
    }
    // A last depth frame the motion capture lost (no pose within 0.02 s): skipped and counted.
    depth << std::fixed << kFirstStamp_s + 5.0 << " depth/lost.png\n";
    std::ofstream(seq_ + "/depth/lost.png", std::ios::binary)
        << engine::EncodeDepthPng(frames_[0].depth_mm, frames_[0].width, frames_[0].height);
    db_ = testing::DatabaseLocation(dir_.File("tum.sqlite"));
    StartServer();
    Ok("POST", "/v1/maps", R"({"id":"home","name":"rendered"})", 201);
    server_->Stop();
  }
  void StartServer() {
    server_ = std::make_unique<testing::ServerProcess>(db_);
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  json Ok(const std::string& method, const std::string& path, const std::string& body = "", int status = 200) {
    httplib::Result r = method == "GET" ? client_->Get(path) : client_->Post(path, body, "application/json");
    EXPECT_TRUE(r) << path;
    if (!r) return json();
    EXPECT_EQ(r->status, status) << path << " " << r->body.substr(0, 300);
    return json::parse(r->body, nullptr, false);
  }
  std::string Import(const std::string& extra = "") { return "import tum --db '" + db_ + "' --map home --dir " + seq_ + " " + extra; }

  testing::TempDir dir_;
  std::string seq_, db_;
  sim::Scene scene_;
  std::vector<sim::Frame> frames_;
  std::vector<Eigen::Isometry3d> poses_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(TumImportTest, ImportsTheSequenceIntoScenesKeyframesAndTheOctomap) {
  const CommandResult run = RunAnchordb(Import());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::printf("anchordb %s\n%s", Import().c_str(), run.output.c_str());
  for (int k = 1; k <= kFrames; ++k) {
    EXPECT_NE(run.output.find("frame " + std::to_string(k) + "/" + std::to_string(kFrames) + " "), std::string::npos)
        << run.output;
  }
  EXPECT_NE(run.output.find("frames/s"), std::string::npos);
  EXPECT_NE(run.output.find("imported 4 frames (1 without a pose"), std::string::npos) << run.output;
  const json summary = json::parse(run.output.substr(run.output.rfind("\n{") + 1), nullptr, false);
  ASSERT_TRUE(summary.is_object()) << run.output;
  EXPECT_EQ(summary["frames_imported"], kFrames);
  EXPECT_EQ(summary["frames_in_depth_txt"], kFrames + 1);
  EXPECT_EQ(summary["frames_without_pose"], 1);
  EXPECT_EQ(summary["keyframes"], 2 * kFrames);  // each scene model's begin and end keyframe
  EXPECT_EQ(summary["keyframes_in_octomap"], 2 * kFrames);

  StartServer();
  const json scenes = Ok("GET", "/v1/maps/home/scenes");
  ASSERT_EQ(scenes["scenes"].size(), static_cast<std::size_t>(kFrames)) << scenes.dump();
  for (const json& s : scenes["scenes"]) EXPECT_EQ(s["status"], "closed");
  const json tree = Ok("GET", "/v1/maps/home/octomap");
  EXPECT_GT(tree["occupied_leaves"].get<int>(), 1000) << tree.dump();

  // Rendered surface points (exact depth, every 32 px) must be occupied, the midpoints of their rays free.
  const PinholeIntrinsics K = Fr1();
  json surface = json::array(), before = json::array();
  for (int k = 0; k < kFrames; ++k) {
    const sim::Frame& f = frames_[k];
    for (int v = 16; v < f.height; v += 32) {
      for (int u = 16; u < f.width; u += 32) {
        const double z = f.true_depth_m[v * f.width + u];
        if (f.depth_mm[v * f.width + u] == 0 || z < 0.6 || z > 4.5) continue;
        const Eigen::Vector3d ray_C((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
        const Eigen::Vector3d p = poses_[k] * (z * ray_C), m = poses_[k] * (0.5 * z * ray_C);
        surface.push_back({p.x(), p.y(), p.z()});
        before.push_back({m.x(), m.y(), m.z()});
      }
    }
  }
  ASSERT_GT(surface.size(), 400u);
  const auto share = [&](const json& points, const std::string& state) {
    const json answer = Ok("POST", "/v1/maps/home/octomap/query", json{{"points", points}}.dump());
    std::size_t n = 0;
    for (const json& r : answer["results"]) n += r["state"] == state;
    return double(n) / points.size();
  };
  const double occupied = share(surface, "occupied"), free = share(before, "free");
  std::printf("surface points occupied: %.3f, ray midpoints free: %.3f (%zu points)\n", occupied, free, surface.size());
  EXPECT_GE(occupied, 0.95);
  EXPECT_GE(free, 0.95);
  // A sequence re-imported with --every 2 --max-frames 1 adds exactly one scene model.
  server_->Stop();
  const CommandResult again = RunAnchordb(Import("--every 2 --max-frames 1"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("frame 1/1 "), std::string::npos) << again.output;
  StartServer();
  EXPECT_EQ(Ok("GET", "/v1/maps/home/scenes")["scenes"].size(), static_cast<std::size_t>(kFrames + 1));
}

TEST_F(TumImportTest, BadInputFailsClearlyAndStoresNothing) {
  const auto expect_refused = [&](const std::string& args, const std::string& message) {
    const CommandResult run = RunAnchordb(args);
    EXPECT_NE(run.exit_code, 0) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(message), std::string::npos) << args << "\n" << run.output;
  };
  expect_refused("import tum --db '" + db_ + "' --map attic --dir " + seq_, "unknown map 'attic'");
  expect_refused("import tum --db '" + db_ + "' --map home --dir " + dir_.File("nowhere"), "no directory");
  expect_refused(Import("--every 0"), "--every");
  expect_refused(Import("--camera fr9"), "fr1, fr2 or fr3");
  // A depth image named but missing.
  std::filesystem::rename(seq_ + "/depth.txt", seq_ + "/depth.good");
  std::ofstream(seq_ + "/depth.txt") << std::fixed << kFirstStamp_s << " depth/missing.png\n";
  expect_refused(Import(), "missing depth image");
  std::ofstream(seq_ + "/depth.txt") << "1305031102.1 depth/a.png extra\n";
  expect_refused(Import(), "depth.txt line 1: expected 'timestamp path'");
  std::filesystem::rename(seq_ + "/depth.good", seq_ + "/depth.txt");
  // A ground-truth line with seven numbers, then one with a quaternion of norm 2.
  std::ofstream(seq_ + "/groundtruth.txt", std::ios::app) << "1305031109.0 1 2 3 0 0 0\n";
  expect_refused(Import(), "groundtruth.txt line 7");
  std::filesystem::remove(seq_ + "/groundtruth.txt");
  expect_refused(Import(), "cannot read");
  StartServer();
  EXPECT_TRUE(Ok("GET", "/v1/maps/home/scenes")["scenes"].empty());
  httplib::Result r = client_->Get("/v1/maps/home/octomap");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
}

}  // namespace
}  // namespace anchordb
