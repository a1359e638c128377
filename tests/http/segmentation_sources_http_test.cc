// The sources and classifiers of furniture segmentation over real HTTP on loopback (issue 16): a room cloud the
// client sends as a PCD / PLY body, the map's OctoMap (its occupied voxels), and segments classified by the stored
// 3D shape model (the newest one, or the one named) instead of by their gross shape alone; bad bodies refused with
// the field named and nothing stored.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/cloud/cloud_io.h"
#include "engine/shapes/virtual_scan.h"
#include "tests/support/furniture_meshes.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace segmentation_sources_http_test {

using nlohmann::json;

// A room in the map frame: floor z = 0 over x in [-2.5, 2.5], y in [-2, 2], a wall at y = 2, the test table
// standing free at (1, 0) and the test cabinet against the wall at (-1, 1.7), each seen from four sides.
const Eigen::Vector2d kTableAt(1.0, 0.0), kCabinetAt(-1.0, 1.7);

std::vector<Eigen::Vector3f> Scans(const std::string& obj, const Eigen::Vector2d& at) {
  const engine::TriangleMesh mesh = engine::ParseObj(obj);
  const engine::ScanCamera cam;
  std::vector<Eigen::Vector3f> out;
  for (const Eigen::Isometry3d& pose : engine::ScanViewpoints(mesh, 4, 0.3, 0.5)) {
    for (Eigen::Vector3f p : engine::DepthToWorldPoints(engine::RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), cam, pose), cam, pose)) {
      p.x() += static_cast<float>(at.x()), p.y() += static_cast<float>(at.y());
      out.push_back(p);
    }
  }
  return out;
}

std::vector<Eigen::Vector3f> RoomCloud() {
  std::vector<Eigen::Vector3f> cloud;
  const float step = 0.02f;
  for (float x = -2.5f; x <= 2.5f; x += step) {
    for (float y = -2.0f; y <= 2.0f; y += step) cloud.emplace_back(x, y, 0.0f);
    for (float z = 0.0f; z <= 2.4f; z += step) cloud.emplace_back(x, 2.0f, z);
  }
  for (const auto& p : Scans(testing::TableObj(), kTableAt)) cloud.push_back(p);
  for (const auto& p : Scans(testing::CabinetObj(), kCabinetAt)) cloud.push_back(p);
  return cloud;
}

class SegmentationSourcesHttpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("db.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(120, 0);
    Json("POST", "/v1/maps", {{"id", "flat"}, {"name", "flat"}}, 201);
  }
  json Check(const httplib::Result& r, int expected, const std::string& what) {
    EXPECT_TRUE(r) << what;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << what << " " << r->body.substr(0, 400);
    return json::parse(r->body, nullptr, false);
  }
  json Json(const std::string& method, const std::string& path, const json& body, int expected) {
    return Check(method == "GET" ? client_->Get(path) : client_->Post(path, body.dump(), "application/json"), expected, method + " " + path);
  }
  json Body(const std::string& path, const std::string& bytes, const std::string& type, int expected) {
    return Check(client_->Post(path, bytes, type), expected, "POST " + path);
  }
  json Await(const json& ticket) {
    const std::string path = "/v1/jobs/" + std::to_string(ticket.value("job", std::int64_t{0}));
    for (int i = 0; i < 2400; ++i) {
      const json j = Json("GET", path, json(), 200);
      const std::string status = j.value("status", "");
      if (status == "succeeded" || status == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << "job " << path << " did not finish";
    return json();
  }
  // The segment whose footprint centre is nearest `at` (and how far it is).
  static std::pair<json, double> Nearest(const json& job, const Eigen::Vector2d& at) {
    json best;
    double best_d = std::numeric_limits<double>::infinity();
    for (const json& s : job["result"]["segments"]) {
      const double d = (Eigen::Vector2d(s["position_m"][0], s["position_m"][1]) - at).norm();
      if (d < best_d) best_d = d, best = s;
    }
    return {best, best_d};
  }
  // The height of a piece's top [m] (its segment starts above the floor's band).
  double Top(const std::string& map, const json& segment) {
    const json piece = Json("GET", "/v1/maps/" + map + "/furniture/" + std::to_string(segment.value("furniture", std::int64_t{0})), json(), 200);
    return piece.value("min_z_m", 0.0) + piece.value("height_m", 0.0);
  }
  // A shape model of two categories named as the grounding knowledge names them (table, cupboard).
  void TrainShapeModel(const std::string& name) {
    const json spec = {{"name", name},
                       {"params", {{"codebook_size", 60}, {"max_keypoints", 250}}},
                       {"samples", {{{"part", "t"}, {"category", "table"}, {"kind", "mesh"}},
                                    {{"part", "c"}, {"category", "cupboard"}, {"kind", "mesh"}}}}};
    httplib::MultipartFormDataItems items = {{"t", testing::TableObj(), "table.obj", "text/plain"},
                                             {"c", testing::CabinetObj(), "cabinet.obj", "text/plain"},
                                             {"spec", spec.dump(), "", "application/json"}};
    const json done = Await(Check(client_->Post("/v1/shape-models", items), 202, "train"));
    ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

// The room cloud's size limit is a setting (serve --segmentation_max_cloud_points), served by GET /v1/settings: a
// cloud over it is refused with 413 naming the body, one within it is queued.
TEST_F(SegmentationSourcesHttpTest, TheCloudLimitIsASettingTheServerEnforces) {
  client_.reset();
  server_ = std::make_unique<testing::ServerProcess>(dir_.File("limited.sqlite"),
                                                     std::vector<std::string>{"--segmentation_max_cloud_points=1000"});
  client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
  client_->set_read_timeout(120, 0);
  Json("POST", "/v1/maps", {{"id", "flat"}, {"name", "flat"}}, 201);
  const json listed = Json("GET", "/v1/settings", json(), 200);
  bool found = false;
  for (const json& setting : listed["settings"]) {
    if (setting["name"] != "segmentation_max_cloud_points") continue;
    found = true;
    EXPECT_EQ(setting["value"], 1000);
  }
  EXPECT_TRUE(found);
  const std::vector<Eigen::Vector3f> room = RoomCloud();
  ASSERT_GT(room.size(), 1000u);
  const std::string path = "/v1/maps/flat/furniture:segment";
  const json e = Body(path, engine::EncodeCloud(room, engine::CloudFormat::kPcdBinary), "application/x-pcd", 413);
  EXPECT_EQ(e["error"]["field"], "body") << e.dump();
  const std::vector<Eigen::Vector3f> part(room.begin(), room.begin() + 1000);
  Body(path, engine::EncodeCloud(part, engine::CloudFormat::kPcdBinary), "application/x-pcd", 202);
}

TEST_F(SegmentationSourcesHttpTest, ClientCloudBodyIsSegmentedAndBadBodiesAreRefused) {
  const std::vector<Eigen::Vector3f> room = RoomCloud();
  const std::string path = "/v1/maps/flat/furniture:segment";
  // Bad bodies: nothing queued, nothing stored.
  const auto refused = [&](const std::string& target, const std::string& bytes, const std::string& type, int status, const std::string& field) {
    const json e = Body(target, bytes, type, status);
    EXPECT_EQ(e["error"]["field"], field) << e.dump();
    EXPECT_FALSE(e["error"]["message"].get<std::string>().empty());
  };
  refused(path, "", "application/x-pcd", 422, "body");
  refused(path, "this is no point cloud", "application/x-pcd", 400, "body");
  std::vector<Eigen::Vector3f> with_nan = room;
  with_nan[7] = Eigen::Vector3f(std::numeric_limits<float>::quiet_NaN(), 0, 0);
  const std::string nan_pcd = engine::EncodeCloud(with_nan, engine::CloudFormat::kPcdBinary);
  refused(path, nan_pcd, "application/x-pcd", 422, "body");
  refused(path + "?skip_nonfinite=maybe", nan_pcd, "application/x-pcd", 400, "skip_nonfinite");
  refused(path + "?shape_model=none_such", nan_pcd, "application/x-pcd", 404, "shape_model");
  refused("/v1/maps/nowhere/furniture:segment", engine::EncodeCloud(room, engine::CloudFormat::kPcdBinary), "application/x-pcd", 404, "map");
  const json source_cloud = Json("POST", path, {{"source", "cloud"}}, 400);
  EXPECT_EQ(source_cloud["error"]["field"], "source");
  EXPECT_TRUE(Json("GET", "/v1/maps/flat/furniture", json(), 200)["furniture"].empty());

  // NaN points left out on request; a PLY body works the same.
  const json job = Await(Body(path + "?skip_nonfinite=true", nan_pcd, "application/x-pcd", 202));
  ASSERT_EQ(job["status"], "succeeded") << job.dump();
  EXPECT_EQ(job["result"]["source"], "cloud");
  EXPECT_TRUE(job["result"]["shape_model"].is_null());  // none stored: by shape alone
  EXPECT_EQ(job["result"]["input_points"], room.size() - 1);
  ASSERT_EQ(job["result"]["segments"].size(), 2u) << job["result"].dump();
  const auto [table, table_d] = Nearest(job, kTableAt);
  EXPECT_LT(table_d, 0.1);
  EXPECT_EQ(table["label"], "table");
  EXPECT_EQ(table["classifier"], "geometry");
  EXPECT_NEAR(Top("flat", table), 0.74, 0.03);
  const auto [cabinet, cabinet_d] = Nearest(job, kCabinetAt);
  EXPECT_LT(cabinet_d, 0.15);
  EXPECT_NEAR(Top("flat", cabinet), 1.3, 0.03);
  EXPECT_EQ(Json("GET", "/v1/maps/flat/furniture", json(), 200)["furniture"].size(), 2u);

  const json again = Await(Body(path, engine::EncodeCloud(room, engine::CloudFormat::kPlyBinary), "application/x-ply", 202));
  ASSERT_EQ(again["status"], "succeeded") << again.dump();
  for (const json& s : again["result"]["segments"]) EXPECT_EQ(s["action"], "updated") << s.dump();
  EXPECT_EQ(Json("GET", "/v1/maps/flat/furniture", json(), 200)["furniture"].size(), 2u);
}

TEST_F(SegmentationSourcesHttpTest, OctomapOccupiedVoxelsAreSegmented) {
  const std::string path = "/v1/maps/flat/furniture:segment";
  const json none = Json("POST", path, {{"source", "octomap"}}, 202);  // queued; the map has no tree yet
  const json failed = Await(none);
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_NE(failed.dump().find("OctoMap"), std::string::npos) << failed.dump();
  const json octomap_keyframes = Json("POST", path, {{"source", "octomap"}, {"keyframes", {1}}}, 400);
  EXPECT_EQ(octomap_keyframes["error"]["field"], "keyframes");

  const std::vector<Eigen::Vector3f> room = RoomCloud();
  Body("/v1/maps/flat/octomap/points?origin=0,-1.5,1.6", engine::EncodeCloud(room, engine::CloudFormat::kPcdBinary), "application/x-pcd", 200);
  const json job = Await(Json("POST", path, {{"source", "octomap"}}, 202));
  ASSERT_EQ(job["status"], "succeeded") << job.dump();
  EXPECT_EQ(job["result"]["source"], "octomap");
  EXPECT_GT(job["result"]["input_points"].get<int>(), 1000);
  ASSERT_EQ(job["result"]["segments"].size(), 2u) << job["result"].dump();
  const auto [table, table_d] = Nearest(job, kTableAt);
  EXPECT_LT(table_d, 0.1);
  EXPECT_NEAR(Top("flat", table), 0.74, 0.05);  // to the voxel
  const auto [cabinet, cabinet_d] = Nearest(job, kCabinetAt);
  EXPECT_LT(cabinet_d, 0.15);
  EXPECT_NEAR(Top("flat", cabinet), 1.3, 0.05);
  const json piece = Json("GET", "/v1/maps/flat/furniture/" + std::to_string(table["furniture"].get<std::int64_t>()), json(), 200);
  EXPECT_TRUE(piece["perceived"].get<bool>());
  EXPECT_TRUE(piece["evidence"].empty());  // no keyframe saw it: the tree did
}

TEST_F(SegmentationSourcesHttpTest, StoredShapeModelClassifiesTheSegments) {
  TrainShapeModel("furniture");
  const std::string room = engine::EncodeCloud(RoomCloud(), engine::CloudFormat::kPcdBinaryCompressed);
  // Not named: the newest stored model classifies.
  const json job = Await(Body("/v1/maps/flat/furniture:segment", room, "application/x-pcd", 202));
  ASSERT_EQ(job["status"], "succeeded") << job.dump();
  EXPECT_EQ(job["result"]["shape_model"], "furniture");
  ASSERT_EQ(job["result"]["segments"].size(), 2u) << job["result"].dump();
  const auto [table, table_d] = Nearest(job, kTableAt);
  ASSERT_LT(table_d, 0.1);
  EXPECT_EQ(table["classifier"], "shape_model:furniture");
  EXPECT_EQ(table["label"], "table");
  const auto [cabinet, cabinet_d] = Nearest(job, kCabinetAt);
  ASSERT_LT(cabinet_d, 0.15);
  EXPECT_EQ(cabinet["classifier"], "shape_model:furniture");
  EXPECT_EQ(cabinet["label"], "cupboard");
  const json stored = Json("GET", "/v1/maps/flat/furniture/" + std::to_string(cabinet["furniture"].get<std::int64_t>()), json(), 200);
  EXPECT_EQ(stored["classifier"], "shape_model:furniture");
  EXPECT_EQ(stored["label"], "cupboard");

  // By shape alone on request (another map: no earlier observation to average with), and by name.
  Json("POST", "/v1/maps", {{"id", "other"}, {"name", "other"}}, 201);
  const json plain = Await(Body("/v1/maps/other/furniture:segment?use_stored_shape_model=false", room, "application/x-pcd", 202));
  ASSERT_EQ(plain["status"], "succeeded") << plain.dump();
  EXPECT_TRUE(plain["result"]["shape_model"].is_null());
  for (const json& s : plain["result"]["segments"]) EXPECT_EQ(s["classifier"], "geometry");
  // The model makes the cabinet more surely a cupboard than its shape alone does.
  const auto [plain_cabinet, plain_d] = Nearest(plain, kCabinetAt);
  ASSERT_LT(plain_d, 0.15);
  const auto share = [](const json& piece, const std::string& category) {
    for (const json& c : piece["categories"]) {
      if (c["category"] == category) return c["probability"].get<double>();
    }
    return 0.0;
  };
  const json plain_stored = Json("GET", "/v1/maps/other/furniture/" + std::to_string(plain_cabinet["furniture"].get<std::int64_t>()), json(), 200);
  EXPECT_GT(share(stored, "cupboard"), share(plain_stored, "cupboard"));
  // A named model classifies even where the stored one would not be used.
  Json("POST", "/v1/maps", {{"id", "third"}, {"name", "third"}}, 201);
  const json named = Await(Body("/v1/maps/third/furniture:segment?shape_model=furniture&use_stored_shape_model=false", room,
                                "application/x-pcd", 202));
  ASSERT_EQ(named["status"], "succeeded") << named.dump();
  EXPECT_EQ(named["result"]["shape_model"], "furniture");
  for (const json& s : named["result"]["segments"]) EXPECT_EQ(s["classifier"], "shape_model:furniture");
}

}  // namespace
}  // namespace anchordb
