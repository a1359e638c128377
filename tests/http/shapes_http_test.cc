// 3D shape models over real HTTP on loopback: training from OBJ meshes and a PCD cloud as a job with a report,
// verification of a PCD / PLY segment and detection in a scene cloud, identical answers after a restart, and bad
// input (empty clouds, NaN points, a category with no samples, broken mesh faces) refused with the field named.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/cloud/cloud_io.h"
#include "engine/shapes/shape_model.h"
#include "engine/shapes/virtual_scan.h"
#include "tests/support/furniture_meshes.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <map>
#include <httplib.h>

#include <chrono>
#include <cmath>
#include <thread>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace shapes_http_test {

using nlohmann::json;

std::vector<Eigen::Vector3f> View(const std::string& obj, double azimuth_rad, const Eigen::Vector3f& offset_m = {0, 0, 0}) {
  const engine::TriangleMesh mesh = engine::ParseObj(obj);
  const engine::ScanCamera cam;
  const auto pose = engine::ScanViewpoints(mesh, 1, azimuth_rad, 0.35)[0];
  auto points = engine::DepthToWorldPoints(engine::RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), cam, pose), cam, pose);
  for (auto& p : points) p += offset_m;
  return points;
}

class ShapesHttpTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> args = {}) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("db.sqlite"), std::move(args));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(120, 0);
  }
  void Restart() {
    client_.reset();
    ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
    Start();
  }
  json Check(const httplib::Result& r, int expected, const std::string& what) {
    EXPECT_TRUE(r) << what;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << what << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json Get(const std::string& path, int expected = 200) { return Check(client_->Get(path), expected, path); }
  json PostCloud(const std::string& path, const std::string& body, int expected) {
    return Check(client_->Post(path, body, "application/x-pcd"), expected, path);
  }
  json Train(const json& spec, const httplib::MultipartFormDataItems& parts, int expected) {
    httplib::MultipartFormDataItems items = parts;
    items.push_back({"spec", spec.dump(), "", "application/json"});
    return Check(client_->Post("/v1/shape-models", items), expected, "train " + spec.dump().substr(0, 80));
  }
  json WaitJob(std::int64_t id) {
    for (int i = 0; i < 2400; ++i) {
      json j = Get("/v1/jobs/" + std::to_string(id));
      if (j.value("status", "") == "succeeded" || j.value("status", "") == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return {};
  }
  static json Spec(const std::string& name) {
    return {{"name", name},
            {"params", {{"codebook_size", 60}, {"max_keypoints", 250}}},
            {"categories", {"table", "cabinet"}},
            {"samples", {{{"part", "t"}, {"category", "table"}, {"kind", "mesh"}},
                         {{"part", "c"}, {"category", "cabinet"}, {"kind", "mesh"}},
                         {{"part", "t_scan"}, {"category", "table"}, {"kind", "cloud"}}}}};
  }
  static httplib::MultipartFormDataItems Parts() {
    return {{"t", testing::TableObj(), "table.obj", "text/plain"},
            {"c", testing::CabinetObj(), "cabinet.obj", "text/plain"},
            {"t_scan", engine::EncodeCloud(View(testing::TableObj(), 0.1), engine::CloudFormat::kPcdBinary), "t.pcd",
             "application/x-pcd"}};
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ShapesHttpTest, TrainClassifyDetectAndRestart) {
  Start();
  const json ticket = Train(Spec("furniture"), Parts(), 202);
  const json done = WaitJob(ticket["job"].get<std::int64_t>());
  ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  const json model = Get("/v1/shape-models/furniture");
  EXPECT_EQ(model["categories"], json({"table", "cabinet"}));
  EXPECT_EQ(model["report"]["samples"], 25);  // 12 virtual scans per mesh + 1 cloud
  EXPECT_EQ(model["report"]["categories"][0]["samples"], 13);
  // The stored options (typed documents, issue 30): the request's parameters over the defaults, the parts as they
  // arrived; the job's request and result as served.
  EXPECT_EQ(model["options"]["params"]["codebook_size"], 60);
  EXPECT_EQ(model["options"]["params"]["max_keypoints"], 250);
  EXPECT_EQ(model["options"]["params"]["voxel_m"], engine::ShapeModelParams{}.voxel_m);
  ASSERT_EQ(model["options"]["parts"].size(), 3u);
  EXPECT_EQ(model["options"]["parts"][0]["kind"], "mesh");
  EXPECT_GT(model["options"]["parts"][0]["triangles"].get<int>(), 0);
  EXPECT_EQ(model["options"]["parts"][2]["kind"], "cloud");
  EXPECT_GT(model["options"]["parts"][2]["points"].get<int>(), 10);
  EXPECT_EQ(model["options"]["mesh_views"], 12);
  EXPECT_EQ(done["request"]["params"], model["options"]["params"]);
  EXPECT_EQ(done["result"]["samples"], model["report"]["samples"]);
  EXPECT_EQ(done["result"]["name"], "furniture");
  EXPECT_GT(model["report"]["categories"][1]["keypoints"].get<int>(), 100);
  EXPECT_EQ(model["report"]["codebook_size"], 60);
  EXPECT_EQ(Get("/v1/shape-models")["shape_models"].size(), 1u);

  const std::string table_pcd = engine::EncodeCloud(View(testing::TableObj(), 2.0), engine::CloudFormat::kPcdBinaryCompressed);
  const std::string cabinet_ply = engine::EncodeCloud(View(testing::CabinetObj(), 4.0), engine::CloudFormat::kPlyBinary);
  const json table = PostCloud("/v1/shape-models/furniture:classify", table_pcd, 200);
  EXPECT_EQ(table["category"], "table") << table.dump();
  EXPECT_NEAR(table["scores"][0]["probability"].get<double>() + table["scores"][1]["probability"].get<double>(), 1.0, 1e-9);
  const json cabinet = PostCloud("/v1/shape-models/furniture:classify", cabinet_ply, 200);
  EXPECT_EQ(cabinet["category"], "cabinet") << cabinet.dump();
  auto scene = View(testing::TableObj(), 0.5, {3.0f, 0.0f, 0.0f});
  const auto beside = View(testing::CabinetObj(), 0.5, {0.0f, 2.0f, 0.0f});
  scene.insert(scene.end(), beside.begin(), beside.end());
  const std::string scene_pcd = engine::EncodeCloud(scene, engine::CloudFormat::kPcdBinary);
  const json detected = PostCloud("/v1/shape-models/furniture:detect", scene_pcd, 200);
  ASSERT_FALSE(detected["detections"].empty()) << detected.dump();
  EXPECT_EQ(detected["points"], scene.size());

  Restart();
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:classify", table_pcd, 200), table);  // bit for bit
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:classify", cabinet_ply, 200), cabinet);
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:detect", scene_pcd, 200), detected);
  EXPECT_EQ(Get("/v1/shape-models/furniture")["report"], model["report"]);
}

// The capability's limits are settings (serve --shapes_max_samples, --shapes_max_points), served by GET /v1/settings
// and enforced with 413.
TEST_F(ShapesHttpTest, LimitsAreSettingsThatTheServerEnforces) {
  Start({"--shapes_max_samples=2", "--shapes_max_points=100"});
  std::map<std::string, json> settings;
  const json listed = Get("/v1/settings");
  for (const json& s : listed["settings"]) settings[s["name"].get<std::string>()] = s["value"];
  EXPECT_EQ(settings["shapes_max_samples"], 2);
  EXPECT_EQ(settings["shapes_max_points"], 100);
  EXPECT_EQ(Train(Spec("big"), Parts(), 413)["error"]["field"], "samples") << "3 samples over a limit of 2";
  // Two samples, within the limit, but a cloud part of more than 100 points.
  json two = Spec("big");
  two["categories"] = {"table"};
  two["samples"] = {two["samples"][0], two["samples"][2]};
  httplib::MultipartFormDataItems parts = Parts();
  parts.erase(parts.begin() + 1);
  ASSERT_GT(View(testing::TableObj(), 0.1).size(), 100u);
  EXPECT_EQ(Train(two, parts, 413)["error"]["field"], "t_scan");
  EXPECT_EQ(Get("/v1/shape-models")["shape_models"].size(), 0u);
}

TEST_F(ShapesHttpTest, BadInputIsRefusedAndNothingIsStored) {
  Start();
  const auto refused = [&](const json& spec, const httplib::MultipartFormDataItems& parts, int status,
                           const std::string& field) {
    const json e = Train(spec, parts, status);
    EXPECT_EQ(e["error"]["field"], field) << spec.dump() << " " << e.dump();
  };
  // A category with no samples.
  json spec = Spec("bad");
  spec["categories"] = {"table", "cabinet", "sofa"};
  refused(spec, Parts(), 422, "categories");
  // A mesh with a broken face (an index beyond its vertices) and one with a two-vertex face.
  auto parts = Parts();
  parts[1].content = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
  refused(Spec("bad"), parts, 422, "c");
  parts[1].content = "v 0 0 0\nv 1 0 0\nf 1 2\n";
  refused(Spec("bad"), parts, 422, "c");
  // An empty cloud, a cloud with NaN points, bytes that are no cloud.
  parts = Parts();
  parts[2].content = "";
  refused(Spec("bad"), parts, 422, "t_scan");
  auto nan_cloud = View(testing::TableObj(), 0.3);
  nan_cloud[3].x() = std::nanf("");
  parts[2].content = engine::EncodeCloud(nan_cloud, engine::CloudFormat::kPcdAscii);
  refused(Spec("bad"), parts, 422, "t_scan");
  parts[2].content = "not a cloud";
  refused(Spec("bad"), parts, 400, "t_scan");
  // A part the spec names but the request lacks; parameters out of range; no multipart at all.
  parts = Parts();
  parts.pop_back();
  refused(Spec("bad"), parts, 400, "samples[2].part");
  spec = Spec("bad");
  spec["params"]["polar_bins"] = 0;
  refused(spec, Parts(), 400, "polar_bins");
  Check(client_->Post("/v1/shape-models", Spec("bad").dump(), "application/json"), 415, "json body");
  EXPECT_EQ(Get("/v1/shape-models")["shape_models"].size(), 0u);

  // Classification: an unknown model, then (with a model) empty, NaN and undecodable bodies.
  const std::string table_pcd = engine::EncodeCloud(View(testing::TableObj(), 2.0), engine::CloudFormat::kPcdBinary);
  Check(client_->Post("/v1/shape-models/none:classify", table_pcd, "application/x-pcd"), 404, "unknown model");
  const json done = WaitJob(Train(Spec("furniture"), Parts(), 202)["job"].get<std::int64_t>());
  ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:classify", "", 422)["error"]["field"], "body");
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:classify", engine::EncodeCloud({}, engine::CloudFormat::kPcdBinary), 422)
                ["error"]["field"], "body");
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:detect", engine::EncodeCloud(nan_cloud, engine::CloudFormat::kPcdAscii), 422)
                ["error"]["field"], "body");
  EXPECT_EQ(PostCloud("/v1/shape-models/furniture:classify", "ply\nformat nonsense\n", 400)["error"]["field"], "body");
}

}  // namespace
}  // namespace anchordb
