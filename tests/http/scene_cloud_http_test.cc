// GET /v1/maps/{map}/scenes/{scene}/cloud over real HTTP: a scene model's static background and movable layer as
// PCD (ascii, binary, binary_compressed) and PLY, in the map and the camera frame, against the rendered frames.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/cloud/cloud_io.h"
#include "engine/scene/depth_image.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace scene_cloud_http_test {

using nlohmann::json;

TEST(SceneCloudHttpTest, StaticAndMovableLayersRoundTripInEveryFormatAndFrame) {
  testing::TempDir dir;
  testing::ServerProcess server(dir.File("clouds.sqlite"));
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  const auto call = [&](const std::string& method, const std::string& path, const std::string& body,
                        const std::string& type) {
    httplib::Result r = method == "GET" ? client.Get(path) : client.Post(path, body, type);
    EXPECT_TRUE(r) << path;
    return r;
  };
  ASSERT_EQ(call("POST", "/v1/maps", R"({"id":"home"})", "application/json")->status, 201);

  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const Eigen::Isometry3d X = setting.X_WorldCameraA;
  sim::SensorModel exact;
  exact.noise = false;
  // A box 1.2 m in front of the camera appears in the second frame: movable, nearer than the background.
  sim::Scene with_box = setting.scene;
  sim::Primitive box;
  box.object_id = 99;
  box.X_WorldPrim.translation() = X * Eigen::Vector3d(0, 0, 1.2);
  box.size_m = {0.3, 0.3, 0.3};
  with_box.primitives.push_back(box);
  with_box.objects.push_back({99, "box", "movable"});
  const sim::Frame first = sim::Render(setting.scene, K, X, exact, 1);
  const sim::Frame second = sim::Render(with_box, K, X, exact, 2);

  const Eigen::Quaterniond q(X.rotation());
  const json open = {{"camera", {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}}},
                     {"pose", {{"position", {X.translation().x(), X.translation().y(), X.translation().z()}},
                               {"orientation", {q.x(), q.y(), q.z(), q.w()}}}}};
  httplib::Result opened = call("POST", "/v1/maps/home/scenes", open.dump(), "application/json");
  ASSERT_EQ(opened->status, 201) << opened->body;
  const std::string scene = "/v1/maps/home/scenes/" + std::to_string(json::parse(opened->body)["id"].get<int>());
  for (const sim::Frame* f : {&first, &second}) {
    httplib::Result r = call("POST", scene + "/frames", engine::EncodeDepthPng(f->depth_mm, f->width, f->height), "image/png");
    ASSERT_EQ(r->status, 200) << r->body;
  }

  const auto cloud = [&](const std::string& query) {
    httplib::Result r = call("GET", scene + "/cloud?" + query, "", "");
    EXPECT_EQ(r->status, 200) << query << " " << r->body.substr(0, 300);
    const engine::DecodedCloud c = engine::DecodeCloud(r->body, 1u << 22);
    EXPECT_EQ(r->get_header_value("X-Points"), std::to_string(c.points.size())) << query;
    return c.points;
  };
  // The background holds the first frame's depths, and the second's where the first measured nothing.
  std::size_t measured_first = 0, measured_either = 0;
  for (std::size_t i = 0; i < first.depth_mm.size(); ++i) {
    measured_first += first.depth_mm[i] > 0;
    measured_either += first.depth_mm[i] > 0 || second.depth_mm[i] > 0;
  }
  const std::vector<Eigen::Vector3f> static_map = cloud("layer=static&format=pcd_binary");
  EXPECT_LE(static_map.size(), measured_either);
  EXPECT_GE(static_map.size(), measured_first * 9 / 10);
  // Every format carries the same points; the camera frame is the map frame moved by the camera pose.
  for (const char* format : {"pcd", "pcd_ascii", "pcd_binary_compressed", "ply", "ply_binary"}) {
    const std::vector<Eigen::Vector3f> again = cloud(std::string("layer=static&format=") + format);
    ASSERT_EQ(again.size(), static_map.size()) << format;
    for (std::size_t i = 0; i < again.size(); i += 97) EXPECT_LT((again[i] - static_map[i]).norm(), 1e-4) << format;
  }
  const std::vector<Eigen::Vector3f> static_camera = cloud("layer=static&frame=camera&format=ply");
  ASSERT_EQ(static_camera.size(), static_map.size());
  for (std::size_t i = 0; i < static_camera.size(); i += 97) {
    EXPECT_LT(((X * static_camera[i].cast<double>()).cast<float>() - static_map[i]).norm(), 1e-3);
  }
  // The movable points lie on the box (its faces within 2 cm), in the map frame.
  const std::vector<Eigen::Vector3f> movable = cloud("layer=movable&format=pcd");
  ASSERT_GT(movable.size(), 500u);
  std::size_t on_box = 0;
  for (const Eigen::Vector3f& p : movable) {
    const Eigen::Vector3d local = box.X_WorldPrim.inverse() * p.cast<double>();
    on_box += (local.cwiseAbs().array() <= box.size_m.array() / 2 + 0.02).all();
  }
  EXPECT_GE(on_box, movable.size() * 95 / 100) << on_box << " of " << movable.size();

  // Bad input: a layer without a cloud, an unknown format, an unknown scene.
  EXPECT_EQ(call("GET", scene + "/cloud?layer=dynamic", "", "")->status, 400);
  EXPECT_EQ(call("GET", scene + "/cloud?format=xyz", "", "")->status, 400);
  EXPECT_EQ(call("GET", "/v1/maps/home/scenes/999/cloud", "", "")->status, 404);
  // Closed and reloaded after a restart (no frame in memory), the movable layer takes its end keyframe's depth.
  ASSERT_EQ(call("POST", scene + ":close", "", "application/json")->status, 200);
  server.Stop();
  testing::ServerProcess restarted(dir.File("clouds.sqlite"));
  httplib::Client again_client("127.0.0.1", restarted.port());
  httplib::Result reloaded = again_client.Get(scene + "/cloud?layer=movable&format=pcd_binary");
  ASSERT_TRUE(reloaded && reloaded->status == 200);
  EXPECT_EQ(engine::DecodeCloud(reloaded->body, 1u << 22).points.size(), movable.size());
  EXPECT_EQ(again_client.Get(scene + "/cloud?layer=dynamic")->status, 400);
}

}  // namespace
}  // namespace anchordb
