// Scene models over real HTTP on loopback (the anchordb binary, a SQLite file): rendered frames in, layers out,
// a restart in the middle, and bad input refused without changing the model.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/scene/depth_image.h"
#include "schema/error.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace scene_http_test {

using nlohmann::json;

class SceneHttpTest : public ::testing::Test {
 public:
  void Start() {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("scenes.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(30, 0);
  }
  void Restart() {
    client_.reset();
    ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
    Start();
  }
  json Post(const std::string& path, const json& body, int expected) {
    auto r = client_->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json Get(const std::string& path) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path << (r ? r->body : "");
    return r ? json::parse(r->body, nullptr, false) : json();
  }
  std::string GetRaw(const std::string& path) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path;
    return r ? r->body : std::string();
  }
  httplib::Result PostFrame(const std::string& path, const std::string& depth_png, const std::string& dynamic_png) {
    httplib::MultipartFormDataItems items = {{"depth", depth_png, "depth.png", "image/png"}};
    if (!dynamic_png.empty()) items.push_back({"dynamic", dynamic_png, "dynamic.png", "image/png"});
    return client_->Post(path, items);
  }
  static json Camera(const PinholeIntrinsics& K) {
    return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
  }
  static json PoseJson(const Eigen::Isometry3d& X) {
    const Eigen::Quaterniond q(X.linear());
    return {{"position", {X.translation().x(), X.translation().y(), X.translation().z()}},
            {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;  // NOLINT: the fixture's state, shared with the scenario
  std::unique_ptr<httplib::Client> client_;
};

// The scenario of acceptance 3: 30 frames of the tabletop; a person comes, carries an object along the table
// and stays in view. Returns the final movable (cleaned), dynamic layers and the last rendered frame.
struct Outcome {
  std::string movable, dynamic, static_png;
  sim::Frame last;
  int object_id = 0, person_id = 0;
};

Outcome RunScenario(SceneHttpTest& t, bool restart_midway, std::unique_ptr<httplib::Client>& client,
                    const std::function<void()>& restart) {
  sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 3);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  Outcome out;
  out.object_id = setting.movable_ids.at(1);
  // A person: a 1.7 m cylinder beside the table, between the camera and the far side.
  out.person_id = 900;
  setting.scene.objects.push_back({out.person_id, "person", "person"});
  sim::Primitive body;
  body.object_id = out.person_id;
  body.shape = sim::Shape::kCylinder;
  body.size_m = {0.2, 0.0, 1.7};
  const Eigen::Vector3d table = setting.surface_point_m;
  const Eigen::Vector3d cam = setting.X_WorldCameraA.translation();
  Eigen::Vector3d side = (table - cam).cross(Eigen::Vector3d::UnitZ()).normalized();
  body.X_WorldPrim.translation() = Eigen::Vector3d(table.x(), table.y(), 0.85) + side * 0.75;
  sim::Scene without_person = setting.scene;
  sim::Scene with_person = setting.scene;
  with_person.primitives.push_back(body);

  const json opened = t.Post("/v1/maps/home/scenes",
                             {{"camera", SceneHttpTest::Camera(K)}, {"pose", SceneHttpTest::PoseJson(setting.X_WorldCameraA)}}, 201);
  const std::string base = "/v1/maps/home/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
  sim::SensorModel sensor;
  for (int i = 0; i < 30; ++i) {
    sim::Scene scene = i < 10 ? without_person : with_person;
    if (i >= 15 && i < 20) {
      Eigen::Isometry3d lift = Eigen::Isometry3d::Identity();
      lift.translation() = Eigen::Vector3d(0, 0, 0.25) + side * 0.1 * (i - 14);  // carried above the table
      sim::MoveObject(scene, out.object_id, lift);
    } else if (i >= 20) {
      Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
      moved.translation() = side * 0.3;  // put down 30 cm further along the table
      sim::MoveObject(scene, out.object_id, moved);
    }
    const sim::Frame f = sim::Render(scene, K, setting.X_WorldCameraA, sensor, 1000 + i);
    std::vector<std::uint8_t> person_mask(f.object_id.size());
    for (std::size_t p = 0; p < person_mask.size(); ++p) person_mask[p] = f.object_id[p] == out.person_id;
    const std::string depth_png = engine::EncodeDepthPng(f.depth_mm, K.width, K.height);
    const std::string mask_png = i >= 10 ? engine::EncodeMaskPng(person_mask, K.width, K.height) : std::string();
    auto r = t.PostFrame(base + "/frames?stamp=" + std::to_string(1'700'000'000'000'000'000LL + i * 33'000'000LL), depth_png, mask_png);
    EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no response");
    if (restart_midway && i == 14) restart();
    out.last = f;
  }
  auto get = [&](const std::string& path) {
    auto r = client->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path;
    return r ? r->body : std::string();
  };
  out.movable = get(base + "/layers/movable?format=raw&clean=true");
  out.dynamic = get(base + "/layers/dynamic?format=raw");
  out.static_png = get(base + "/layers/static?format=png");
  return out;
}

TEST_F(SceneHttpTest, MovedObjectMovablePersonDynamicRestStaticAndRestartChangesNothing) {
  Start();
  Post("/v1/maps", {{"id", "home"}}, 201);
  const Outcome straight = RunScenario(*this, false, client_, [] {});
  const Outcome restarted = RunScenario(*this, true, client_, [this] { Restart(); });

  const Outcome& o = straight;
  ASSERT_EQ(o.movable.size(), o.last.object_id.size());
  std::size_t object = 0, object_movable = 0, person = 0, person_dynamic = 0, rest = 0, rest_flagged = 0;
  for (std::size_t p = 0; p < o.movable.size(); ++p) {
    const int id = o.last.object_id[p];
    if (o.last.depth_mm[p] == 0) continue;
    if (id == o.object_id) ++object, object_movable += o.movable[p] != 0;
    else if (id == o.person_id) ++person, person_dynamic += o.dynamic[p] != 0;
    else ++rest, rest_flagged += (o.movable[p] != 0 || o.dynamic[p] != 0);
  }
  std::printf("object %zu px, %zu movable; person %zu px, %zu dynamic; rest %zu px, %zu flagged\n", object,
              object_movable, person, person_dynamic, rest, rest_flagged);
  ASSERT_GT(object, 300u);
  ASSERT_GT(person, 1000u);
  EXPECT_GT(static_cast<double>(object_movable) / object, 0.9) << object_movable << "/" << object;
  EXPECT_EQ(person_dynamic, person);
  EXPECT_LT(static_cast<double>(rest_flagged) / rest, 0.005) << rest_flagged << "/" << rest;
  // A graceful restart in the middle of the observation changes nothing in the outcome.
  EXPECT_EQ(restarted.movable, straight.movable);
  EXPECT_EQ(restarted.dynamic, straight.dynamic);
  EXPECT_EQ(restarted.static_png, straight.static_png);
}

TEST_F(SceneHttpTest, BadInputIsRefusedAndChangesNothing) {
  Start();
  Post("/v1/maps", {{"id", "home"}}, 201);
  const PinholeIntrinsics K{64, 48, 60.0, 60.0, 31.5, 23.5};
  const json pose = {{"position", {0, 0, 1}}, {"orientation", {0, 0, 0, 1}}};
  const std::int64_t id = Post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", pose}}, 201)["id"];
  const std::string base = "/v1/maps/home/scenes/" + std::to_string(id);
  std::vector<std::uint16_t> depth(64 * 48, 1500);
  auto ok = client_->Post(base + "/frames", engine::EncodeDepthPng(depth, 64, 48), "image/png");
  ASSERT_TRUE(ok && ok->status == 200) << (ok ? ok->body : "");
  const std::string static_before = GetRaw(base + "/layers/static?format=raw");

  auto expect_error = [&](httplib::Result r, int status, const std::string& code) {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    const json e = json::parse(r->body, nullptr, false);
    EXPECT_EQ(e["error"]["code"], code) << r->body;
    EXPECT_EQ(Get(base)["frames"], 1);
    EXPECT_EQ(GetRaw(base + "/layers/static?format=raw"), static_before);
  };
  // Wrong size for the intrinsics.
  std::vector<std::uint16_t> big(80 * 48, 1000);
  expect_error(client_->Post(base + "/frames", engine::EncodeDepthPng(big, 80, 48), "image/png"), 422, "unprocessable");
  // An 8-bit PNG where 16-bit depth is needed.
  std::vector<std::uint8_t> grey(64 * 48, 7);
  expect_error(client_->Post(base + "/frames", engine::EncodeGreyPng(grey, 64, 48), "image/png"), 400, "invalid_argument");
  // A PNG whose header declares 60000 x 60000 pixels (a decompression bomb: a few bytes, 7 GB decoded) is refused
  // from its header, before anything is allocated: the camera's size does not match.
  std::string bomb = engine::EncodeDepthPng(depth, 64, 48);
  const auto put_be32 = [&](std::size_t offset, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) bomb[offset + k] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
  };
  put_be32(16, 60000);
  put_be32(20, 60000);
  expect_error(client_->Post(base + "/frames", bomb, "image/png"), 422, "unprocessable");
  // The same header decoded without a camera to compare with: refused for its size, not allocated.
  try {
    engine::DecodeDepthPng(bomb, "depth");
    ADD_FAILURE() << "a 60000 x 60000 PNG was decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kPayloadTooLarge) << e.what();
  }
  // A truncated raw body.
  std::string raw(reinterpret_cast<const char*>(depth.data()), depth.size() * 2);
  expect_error(client_->Post(base + "/frames", raw.substr(0, raw.size() - 10), "application/octet-stream"), 400, "invalid_argument");
  // Not an image at all, and an unsupported media type.
  expect_error(client_->Post(base + "/frames", "hello", "image/png"), 400, "invalid_argument");
  expect_error(client_->Post(base + "/frames", raw, "text/plain"), 415, "unsupported_media_type");
  // Unknown model and unknown map.
  expect_error(client_->Post("/v1/maps/home/scenes/999/frames", raw, "application/octet-stream"), 404, "not_found");
  expect_error(client_->Post("/v1/maps/nope/scenes/" + std::to_string(id) + "/frames", raw, "application/octet-stream"), 404, "not_found");
  // Bad poses and cameras when opening: NaN is not JSON, 1e999 overflows, a non-unit quaternion, a zero focal length.
  const std::string before_list = GetRaw("/v1/maps/home/scenes");
  auto open_raw = [&](const std::string& body) { return client_->Post("/v1/maps/home/scenes", body, "application/json"); };
  const std::string cam = Camera(K).dump();
  auto r1 = open_raw(R"({"camera":)" + cam + R"(,"pose":{"position":[NaN,0,0],"orientation":[0,0,0,1]}})");
  ASSERT_TRUE(r1);
  EXPECT_EQ(r1->status, 400);
  auto r2 = open_raw(R"({"camera":)" + cam + R"(,"pose":{"position":[1e999,0,0],"orientation":[0,0,0,1]}})");
  ASSERT_TRUE(r2);
  EXPECT_EQ(r2->status, 400);
  auto r3 = open_raw(R"({"camera":)" + cam + R"(,"pose":{"position":[0,0,0],"orientation":[0,0,0,2]}})");
  ASSERT_TRUE(r3);
  EXPECT_EQ(r3->status, 422);
  EXPECT_EQ(json::parse(r3->body)["error"]["field"], "pose.orientation");
  json bad_cam = Camera(K);
  bad_cam["fx"] = 0;
  Post("/v1/maps/home/scenes", {{"camera", bad_cam}, {"pose", pose}}, 422);
  EXPECT_EQ(GetRaw("/v1/maps/home/scenes"), before_list);
  // A frame to a closed model.
  Post(base + ":close", json::object(), 200);
  const std::string closed_static = GetRaw(base + "/layers/static?format=raw");
  auto r4 = client_->Post(base + "/frames", raw, "application/octet-stream");
  ASSERT_TRUE(r4);
  EXPECT_EQ(r4->status, 409);
  EXPECT_EQ(GetRaw(base + "/layers/static?format=raw"), closed_static);
  // Keyframes exist (begin at the first frame, end at close), compressed, readable as PNG.
  const json scene = Get(base);
  ASSERT_EQ(scene["keyframes"].size(), 2u);
  const json kf = Get("/v1/maps/home/keyframes/" + std::to_string(scene["keyframes"][1]["id"].get<std::int64_t>()));
  EXPECT_EQ(kf["kind"], "end");
  EXPECT_LE(kf["compression_ratio"].get<double>(), 0.4);
  const std::string png = GetRaw("/v1/maps/home/keyframes/" + std::to_string(kf["id"].get<std::int64_t>()) + "/depth");
  const engine::DepthImage back = engine::DecodeDepthPng(png, "png");
  EXPECT_EQ(back.pixels, depth);
}

}  // namespace
}  // namespace anchordb

namespace anchordb {
namespace scene_http_test {

// Issue 4, acceptance 5: A is observed and closed; the object is moved meanwhile; B, opened elsewhere, reports the
// moved object movable in its first frames without having seen it move -- the merge carried A's background over.
TEST_F(SceneHttpTest, ObjectMovedMeanwhileIsMovableInTheFirstFramesOfAnotherViewpoint) {
  Start();
  Post("/v1/maps", {{"id", "home"}}, 201);
  sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 2);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const int object = setting.movable_ids.at(1);
  sim::SensorModel sensor;
  const json a = Post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(setting.X_WorldCameraA)}}, 201);
  const std::string path_a = "/v1/maps/home/scenes/" + std::to_string(a["id"].get<std::int64_t>());
  EXPECT_FALSE(a["merge"]["pending"].get<bool>());  // nothing earlier to merge
  for (int i = 0; i < 8; ++i) {
    const sim::Frame f = sim::Render(setting.scene, K, setting.X_WorldCameraA, sensor, 300 + i);
    auto r = client_->Post(path_a + "/frames", engine::EncodeDepthPng(f.depth_mm, K.width, K.height), "image/png");
    ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  }
  Post(path_a + ":close", json::object(), 200);
  // Meanwhile, the object is moved 20 cm along the table (nobody watches).
  const Eigen::Vector3d side =
      (setting.surface_point_m - setting.X_WorldCameraA.translation()).cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d move = Eigen::Isometry3d::Identity();
  move.translation() = side * 0.2;
  sim::MoveObject(setting.scene, object, move);

  const json b = Post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(setting.X_WorldCameraB)}}, 201);
  ASSERT_EQ(b["merge"]["candidates"].size(), 1u) << b.dump();
  EXPECT_TRUE(b["merge"]["pending"].get<bool>());
  const std::string path_b = "/v1/maps/home/scenes/" + std::to_string(b["id"].get<std::int64_t>());
  sim::Frame last;
  for (int i = 0; i < 3; ++i) {
    last = sim::Render(setting.scene, K, setting.X_WorldCameraB, sensor, 400 + i);
    auto r = client_->Post(path_b + "/frames", engine::EncodeDepthPng(last.depth_mm, K.width, K.height), "image/png");
    ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
  }
  const json scene = Get(path_b);
  const json& report = scene["merge"];
  EXPECT_TRUE(report["performed"].get<bool>()) << report.dump();
  ASSERT_EQ(report["models_used"].size(), 1u);
  EXPECT_TRUE(report["models_used"][0]["icp"]["converged"].get<bool>());
  EXPECT_GT(report["models_used"][0]["pixels"]["replaced_farther"].get<int>(), 100);
  const std::string movable = GetRaw(path_b + "/layers/movable?format=raw&clean=true");
  std::size_t object_px = 0, object_movable = 0, other_px = 0, other_movable = 0;
  for (std::size_t p = 0; p < movable.size(); ++p) {
    if (last.depth_mm[p] == 0) continue;
    if (last.object_id[p] == object) ++object_px, object_movable += movable[p] != 0;
    else ++other_px, other_movable += movable[p] != 0;
  }
  std::printf("B after 3 frames: object %zu/%zu movable, elsewhere %zu/%zu\n", object_movable, object_px, other_movable, other_px);
  ASSERT_GT(object_px, 300u);
  EXPECT_GT(static_cast<double>(object_movable) / object_px, 0.65);  // measured 0.70: its base is within theta of the table
  EXPECT_LT(static_cast<double>(other_movable) / other_px, 0.01);
  // Reopening at (almost) A's viewpoint supersedes A.
  const json c = Post("/v1/maps/home/scenes", {{"camera", Camera(K)}, {"pose", PoseJson(setting.X_WorldCameraA)}}, 201);
  const std::string path_c = "/v1/maps/home/scenes/" + std::to_string(c["id"].get<std::int64_t>());
  const sim::Frame fc = sim::Render(setting.scene, K, setting.X_WorldCameraA, sensor, 500);
  auto rc = client_->Post(path_c + "/frames", engine::EncodeDepthPng(fc.depth_mm, K.width, K.height), "image/png");
  ASSERT_TRUE(rc && rc->status == 200);
  EXPECT_EQ(Get(path_a)["status"], "superseded") << Get(path_c)["merge"].dump();
  EXPECT_EQ(Get(path_a)["superseded_by"], c["id"]);
  EXPECT_EQ(Get(path_b)["status"], "observing");
}

}  // namespace
}  // namespace anchordb
