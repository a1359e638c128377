// The pose uncertainty a client gives when it opens a scene model (issue 13), over real HTTP on loopback (the
// anchordb binary, a SQLite file): pose_sigma or a ROS-style pose_covariance is stored with the model and shown
// back, bad input is refused with a JSON error naming the field and changes nothing, and the merge report of a
// later model carries the registration's verdict and conditioning.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/scene/depth_image.h"
#include "sim/renderer.h"
#include "sim/scenario_driver.h"
#include "tests/engine/registration_scenes.h"
#include "tests/support/scene_request_json.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace scene_pose_uncertainty_http_test {

using nlohmann::json;
namespace rs = registration_scenes;

using testing::PoseJson;
const auto& Camera = testing::CameraJson;
json Diagonal(double t_var, double r_var) {
  json c = json::array();
  for (int i = 0; i < 36; ++i) c.push_back(i % 7 == 0 ? (i < 18 ? t_var : r_var) : 0.0);
  return c;
}

// POSTs a JSON body; the status and the parsed answer (0 and null when nothing answered).
std::pair<int, json> PostJson(httplib::Client& client, const std::string& path, const json& body) {
  auto r = client.Post(path, body.dump(), "application/json");
  EXPECT_TRUE(r) << path;
  return r ? std::pair{r->status, json::parse(r->body, nullptr, false)} : std::pair{0, json()};
}

TEST(ScenePoseUncertaintyHttpTest, PoseSigmaOrCovarianceIsStoredBadInputIsRefusedAndTheMergeReportsTheRegistration) {
  testing::TempDir dir;
  testing::ServerProcess server(dir.File("pose.sqlite"));
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  const auto post = [&](const std::string& path, const json& body) { return PostJson(client, path, body); };
  ASSERT_EQ(post("/v1/maps", {{"id", "home"}}).first, 201);
  const PinholeIntrinsics K = rs::Kinect(320, 240);
  const sim::Scene scene = rs::SparseRoom();
  const json open_a = {{"camera", Camera(K)}, {"pose", PoseJson(rs::ViewA())}};

  // Bad input: 400 (wrong types) or 422 (impossible values), the field named, no model opened.
  struct Bad {
    json fields;
    int status;
    std::string field;
  };
  json asymmetric = Diagonal(1e-4, 1e-3), indefinite = Diagonal(1e-4, 1e-3), negative_sigma = json::object();
  asymmetric[1] = 1e-5;
  indefinite[0] = -1e-4;
  json too_long = Diagonal(1e-4, 1e-3);
  too_long.push_back(0.0);
  json too_short = Diagonal(1e-4, 1e-3);
  too_short.erase(too_short.size() - 1);
  const std::vector<Bad> bad = {
      {{{"pose_sigma", {{"translation_m", -0.01}, {"rotation_rad", 0.02}}}}, 422, "pose_sigma.translation_m"},
      {{{"pose_sigma", {{"translation_m", 0.01}, {"rotation_rad", 4.0}}}}, 422, "pose_sigma.rotation_rad"},
      {{{"pose_sigma", {{"translation_m", "0.01"}, {"rotation_rad", 0.02}}}}, 400, "pose_sigma.translation_m"},
      {{{"pose_sigma", {{"translation_m", 0.01}}}}, 400, "pose_sigma.rotation_rad"},
      {{{"pose_sigma", 0.02}}, 400, "pose_sigma"},
      {{{"pose_sigma", {{"translation_m", 0.01}, {"rotation_rad", 0.02}}}, {"pose_covariance", Diagonal(1e-4, 1e-3)}},
       422, "pose_covariance"},
      {{{"pose_covariance", too_short}}, 422, "pose_covariance"},
      {{{"pose_covariance", too_long}}, 400, "pose_covariance"},
      {{{"pose_covariance", asymmetric}}, 422, "pose_covariance"},
      {{{"pose_covariance", indefinite}}, 422, "pose_covariance"},
      {{{"pose_covariance", json::array({"a"})}}, 400, "pose_covariance"},
  };
  for (const Bad& b : bad) {
    json body = open_a;
    body.update(b.fields);
    const auto [status, e] = post("/v1/maps/home/scenes", body);
    EXPECT_EQ(status, b.status) << body.dump() << " " << e.dump();
    EXPECT_EQ(e["error"]["field"], b.field) << e.dump();
  }
  auto list = client.Get("/v1/maps/home/scenes");
  ASSERT_TRUE(list && list->status == 200);
  EXPECT_TRUE(json::parse(list->body)["scenes"].empty()) << list->body;

  // A: pose_sigma, stored and shown back as its covariance; four frames; closed.
  json body_a = open_a;
  body_a["pose_sigma"] = {{"translation_m", 0.02}, {"rotation_rad", 0.03}};
  const auto [status_a, a] = post("/v1/maps/home/scenes", body_a);
  ASSERT_EQ(status_a, 201) << a.dump();
  ASSERT_EQ(a["pose_covariance"].size(), 36u);
  EXPECT_NEAR(a["pose_covariance"][0].get<double>(), 4e-4, 1e-12);
  EXPECT_NEAR(a["pose_covariance"][35].get<double>(), 9e-4, 1e-12);
  EXPECT_EQ(a["pose_covariance"][1].get<double>(), 0.0);
  const std::string path_a = "/v1/maps/home/scenes/" + std::to_string(a["id"].get<std::int64_t>());
  for (int i = 0; i < 4; ++i) {
    const sim::Frame f = sim::Render(scene, K, rs::ViewA(), sim::SensorModel{}, 10 + i);
    auto r = client.Post(path_a + "/frames", engine::EncodeDepthPng(f.depth_mm, K.width, K.height), "image/png");
    ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  }
  ASSERT_EQ(post(path_a + ":close", json::object()).first, 200);

  // B: opened 2 cm / 1 deg off with a ROS covariance; its first frame merges A and reports the registration.
  const Eigen::Isometry3d B_stored = rs::Perturbed(rs::ViewB(), {0.02, 0.0, 0.0}, {0.0, 0.0, 0.0175});
  const auto [status_b, b] = post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(B_stored)},
                                                          {"pose_covariance", Diagonal(9e-4, 1.2e-3)}});
  ASSERT_EQ(status_b, 201) << b.dump();
  EXPECT_NEAR(b["pose_covariance"][21].get<double>(), 1.2e-3, 1e-12);
  ASSERT_EQ(b["merge"]["candidates"].size(), 1u) << b.dump();
  const std::string path_b = "/v1/maps/home/scenes/" + std::to_string(b["id"].get<std::int64_t>());
  const sim::Frame f = sim::Render(scene, K, rs::ViewB(), sim::SensorModel{}, 20);
  auto r = client.Post(path_b + "/frames", engine::EncodeDepthPng(f.depth_mm, K.width, K.height), "image/png");
  ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  auto got = client.Get(path_b);
  ASSERT_TRUE(got && got->status == 200);
  const json report = json::parse(got->body)["merge"];
  ASSERT_EQ(report["models_used"].size(), 1u) << report.dump();
  const json& icp = report["models_used"][0]["icp"];
  EXPECT_TRUE(icp["applied"].get<bool>()) << icp.dump();
  EXPECT_EQ(icp["verdict"].get<std::string>().rfind("accepted", 0), 0u) << icp.dump();
  ASSERT_EQ(icp["relative_information"].size(), 6u);
  EXPECT_LE(icp["relative_information"][0].get<double>(), icp["relative_information"][5].get<double>());
  EXPECT_GE(icp["unobservable_directions"].get<int>(), 0);
  ASSERT_EQ(icp["remaining_sigma"].size(), 6u);
  // The registration learnt something: the remaining translation uncertainty is below the prior's (>= 3 cm).
  EXPECT_LT(icp["remaining_sigma"][0].get<double>(), 0.03) << icp.dump();
  EXPECT_GE(icp["mahalanobis2"].get<double>(), 0.0);
  // The premises used that uncertainty, and the model was merged.
  const json& premises = report["models_used"][0]["premises"];
  EXPECT_TRUE(premises["merged"].get<bool>()) << premises.dump();
  EXPECT_EQ(premises["fallback"].get<std::string>(), "");
  EXPECT_GT(premises["tolerance_px"].get<double>(), 0.0);
  EXPECT_GT(report["models_used"][0]["pixels"]["supported"].get<std::size_t>(), 0u);
}

// Never worse than no merge, over HTTP: a view of nothing but the floor cannot tell where along the floor the
// camera stands, and with 10 cm / 0.1 rad of pose uncertainty on both models the earlier one is not merged at all;
// the report says so and why, and the new model starts as a fresh one (nothing supported, replaced or filled).
TEST(ScenePoseUncertaintyHttpTest, AnUnobservableRegistrationUnderAWidePriorFallsBackAndSaysWhy) {
  testing::TempDir dir;
  testing::ServerProcess server(dir.File("fallback.sqlite"));
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60, 0);
  const auto post = [&](const std::string& path, const json& body) { return PostJson(client, path, body); };
  ASSERT_EQ(post("/v1/maps", {{"id", "home"}}).first, 201);
  // Full resolution: at 320 x 240 the sensor's disparity terraces on the far floor lend its in-plane motion enough
  // apparent information that only 2 of the 3 directions count as unobservable (an open defect, issue 13's note).
  const PinholeIntrinsics K = rs::Kinect(640, 480);
  sim::Scene floor;
  sim::AddBox(floor, 1, "floor", {3.0, 0.0, -0.05}, {8.0, 8.0, 0.1}, 0.0);
  const Eigen::Isometry3d A = sim::LookAt({0.0, -0.3, 1.2}, {2.5, -0.3, 0.0});
  const Eigen::Isometry3d B = sim::LookAt({0.2, 0.2, 1.2}, {2.5, 0.0, 0.0});
  const json wide = {{"translation_m", 0.1}, {"rotation_rad", 0.1}};
  Eigen::Isometry3d A_stored = A;
  A_stored.translation() += Eigen::Vector3d(0.06, -0.05, 0.0);  // the localisation error, along the floor
  const auto [status_a, a] = post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(A_stored)}, {"pose_sigma", wide}});
  ASSERT_EQ(status_a, 201) << a.dump();
  const std::string path_a = "/v1/maps/home/scenes/" + std::to_string(a["id"].get<std::int64_t>());
  for (int i = 0; i < 4; ++i) {
    const sim::Frame f = sim::Render(floor, K, A, sim::SensorModel{}, 30 + i);
    auto r = client.Post(path_a + "/frames", engine::EncodeDepthPng(f.depth_mm, K.width, K.height), "image/png");
    ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  }
  ASSERT_EQ(post(path_a + ":close", json::object()).first, 200);
  const auto [status_b, b] = post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(B)}, {"pose_sigma", wide}});
  ASSERT_EQ(status_b, 201) << b.dump();
  ASSERT_EQ(b["merge"]["candidates"].size(), 1u) << b.dump();
  const std::string path_b = "/v1/maps/home/scenes/" + std::to_string(b["id"].get<std::int64_t>());
  const sim::Frame f = sim::Render(floor, K, B, sim::SensorModel{}, 40);
  auto r = client.Post(path_b + "/frames", engine::EncodeDepthPng(f.depth_mm, K.width, K.height), "image/png");
  ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  auto got = client.Get(path_b);
  ASSERT_TRUE(got && got->status == 200);
  const json report = json::parse(got->body)["merge"];
  ASSERT_EQ(report["models_used"].size(), 1u) << report.dump();
  const json& used = report["models_used"][0];
  EXPECT_GE(used["icp"]["unobservable_directions"].get<int>(), 2) << used.dump();
  EXPECT_FALSE(used["premises"]["merged"].get<bool>()) << used.dump();
  EXPECT_NE(used["premises"]["fallback"].get<std::string>().find("not merged"), std::string::npos) << used.dump();
  EXPECT_GT(used["premises"]["tolerance_px"].get<double>(), 32.0) << used.dump();
  const json& px = used["pixels"];
  EXPECT_EQ(px["supported"].get<std::size_t>() + px["replaced_farther"].get<std::size_t>() +
                px["rear_projected"].get<std::size_t>() + px["filled_unknown"].get<std::size_t>(),
            0u) << px.dump();
}

}  // namespace
}  // namespace anchordb
