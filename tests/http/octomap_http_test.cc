// The octomap routes over real HTTP on loopback (the anchordb binary, a SQLite file): configure, clouds in every
// PCD / PLY form, queries, .ot / .bt round trips, the operator's audited box clear, a restart, and bad input that
// gets a clear JSON error and changes nothing.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/cloud/cloud_io.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <limits>
#include <map>
#include <nlohmann/json.hpp>

namespace anchordb {
namespace octomap_http_test {

using nlohmann::json;

// A wall of points at x = `x_m` facing the origin (y in [y0, y0 + 0.5], z in [0.5, 1.0]), 1 cm apart.
std::vector<Eigen::Vector3f> Wall(float x_m, float y0_m) {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i <= 50; ++i) {
    for (int j = 0; j <= 50; ++j) points.emplace_back(x_m, y0_m + 0.01f * i, 0.5f + 0.01f * j);
  }
  return points;
}

class OctomapHttpTest : public ::testing::Test {
 protected:
  void SetUp() override { Start(); }
  void Start() {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("octomap.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  std::pair<int, json> Send(const std::string& method, const std::string& path, const std::string& body,
                            const std::string& type = "application/json") {
    httplib::Result r = method == "GET"   ? client_->Get(path)
                        : method == "PUT" ? client_->Put(path, body, type)
                                          : client_->Post(path, body, type);
    EXPECT_TRUE(r) << method << " " << path;
    if (!r) return {0, json()};
    last_body_ = r->body;
    return {r->status, json::parse(r->body, nullptr, false)};
  }
  json Ok(const std::string& method, const std::string& path, const std::string& body = "{}",
          const std::string& type = "application/json", int status = 200) {
    auto [code, j] = Send(method, path, body, type);
    EXPECT_EQ(code, status) << method << " " << path << " " << j.dump().substr(0, 500);
    return j;
  }
  // The answer is a JSON error with `status` and `field`, and the tree's version did not move.
  void ExpectRefused(const std::string& method, const std::string& path, const std::string& body, int status,
                     const std::string& field, const std::string& type = "application/json") {
    const std::int64_t before = Version();
    auto [code, j] = Send(method, path, body, type);
    EXPECT_EQ(code, status) << path << " " << j.dump();
    ASSERT_TRUE(j.contains("error")) << last_body_.substr(0, 300);
    EXPECT_EQ(j["error"].value("field", ""), field) << j.dump();
    EXPECT_FALSE(j["error"].value("message", "").empty());
    EXPECT_EQ(Version(), before) << path;
  }
  std::int64_t Version(const std::string& map = "home") {
    httplib::Result r = client_->Get("/v1/maps/" + map + "/octomap");
    if (!r || r->status != 200) return -1;
    return json::parse(r->body)["version"].get<std::int64_t>();
  }
  std::string GetBytes(const std::string& path) {
    httplib::Result r = client_->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path << " " << (r ? r->body.substr(0, 300) : "");
    return r ? r->body : "";
  }
  std::vector<std::string> States(const json& points, const std::string& map = "home") {
    const json answer = Ok("POST", "/v1/maps/" + map + "/octomap/query", json{{"points", points}}.dump());
    std::vector<std::string> out;
    for (const json& r : answer["results"]) out.push_back(r["state"]);
    return out;
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
  std::string last_body_;
};

TEST_F(OctomapHttpTest, CloudsInEveryFormatBuildATreeThatAnswersQueriesAndSurvivesARestart) {
  Ok("POST", "/v1/maps", R"({"id":"home"})", "application/json", 201);
  auto [missing, error] = Send("GET", "/v1/maps/home/octomap", "");
  EXPECT_EQ(missing, 404);
  EXPECT_EQ(error["error"]["field"], "octomap");
  const json configured = Ok("PUT", "/v1/maps/home/octomap", R"({"resolution_m":0.05,"max_range_m":6})");
  EXPECT_EQ(configured["sensor_model"]["prob_hit"], 0.7);
  EXPECT_EQ(configured["sensor_model"]["clamp_max"], 0.97);
  EXPECT_EQ(configured["leaves"], 0);

  // One wall per cloud format, side by side along y.
  const std::vector<engine::CloudFormat> formats = {engine::CloudFormat::kPcdAscii, engine::CloudFormat::kPcdBinary,
                                                    engine::CloudFormat::kPcdBinaryCompressed,
                                                    engine::CloudFormat::kPlyAscii, engine::CloudFormat::kPlyBinary};
  json wall_points = json::array();
  for (std::size_t i = 0; i < formats.size(); ++i) {
    const float y0 = -1.5f + 0.6f * static_cast<float>(i);
    const std::string body = engine::EncodeCloud(Wall(2.0f, y0), formats[i]);
    const json inserted = Ok("POST", "/v1/maps/home/octomap/points?origin=0,0,0.75", body, "application/octet-stream");
    EXPECT_EQ(inserted["points"], 51 * 51) << i;
    EXPECT_GT(inserted["occupied_updates"].get<int>(), 50) << i;
    wall_points.push_back({2.01, y0 + 0.25, 0.75});
  }
  for (const std::string& s : States(wall_points)) EXPECT_EQ(s, "occupied");
  EXPECT_EQ(States({{1.0, 0.0, 0.75}, {3.0, 0.0, 0.75}, {0.0, 0.0, 3.0}}),
            (std::vector<std::string>{"free", "unknown", "unknown"}));

  const json hit = Ok("POST", "/v1/maps/home/octomap/ray", R"({"origin":[0,0,0.75],"direction":[1,0,0]})");
  EXPECT_TRUE(hit["hit"].get<bool>());
  EXPECT_NEAR(hit["end"][0].get<double>(), 2.0, 0.06);
  const json voxels = Ok("POST", "/v1/maps/home/octomap/voxels", R"({"min":[1.9,-2,0],"max":[2.1,2,2]})");
  EXPECT_GT(voxels["count"].get<int>(), 400);
  const json info = Ok("GET", "/v1/maps/home/octomap");
  EXPECT_EQ(info["occupied_leaves"], voxels["count"]);
  EXPECT_GT(info["stored_bytes"].get<int>(), 0);

  // Occupied centres out, as PCD and PLY: as many points as occupied leaves.
  for (const char* format : {"pcd_ascii", "pcd", "ply"}) {
    const engine::DecodedCloud centres = engine::DecodeCloud(GetBytes(std::string("/v1/maps/home/octomap?format=") + format), 1 << 20);
    EXPECT_EQ(static_cast<int>(centres.points.size()), info["occupied_leaves"].get<int>()) << format;
  }

  // A restart: the stored tree answers the same.
  const std::string ot_before = GetBytes("/v1/maps/home/octomap?format=ot");
  server_->Stop();
  Start();
  EXPECT_EQ(Version(), info["version"].get<std::int64_t>());
  EXPECT_EQ(GetBytes("/v1/maps/home/octomap?format=ot"), ot_before);
  for (const std::string& s : States(wall_points)) EXPECT_EQ(s, "occupied");
}

TEST_F(OctomapHttpTest, OtAndBtRoundTripThroughTheApiAndTheOperatorClearIsAudited) {
  Ok("POST", "/v1/maps", R"({"id":"home"})", "application/json", 201);
  Ok("POST", "/v1/maps", R"({"id":"copy"})", "application/json", 201);
  const std::string cloud = engine::EncodeCloud(Wall(2.0f, -0.25f), engine::CloudFormat::kPcdBinary);
  Ok("POST", "/v1/maps/home/octomap/points?origin=0,0,0.75", cloud, "application/octet-stream");
  Ok("POST", "/v1/maps/home/octomap/points?origin=0,0.1,0.75", cloud, "application/octet-stream");
  const std::string ot = GetBytes("/v1/maps/home/octomap?format=ot");
  Ok("PUT", "/v1/maps/copy/octomap?format=ot", ot, "application/octet-stream");
  EXPECT_EQ(GetBytes("/v1/maps/copy/octomap?format=ot"), ot);  // log-odds kept
  const std::string bt = GetBytes("/v1/maps/home/octomap?format=bt");
  Ok("PUT", "/v1/maps/copy/octomap", bt, "application/octet-stream");  // format from the header
  EXPECT_EQ(GetBytes("/v1/maps/copy/octomap?format=bt"), bt);

  const json cleared = Ok("POST", "/v1/maps/home/octomap:clear", R"({"min":[1.9,-0.1,0.6],"max":[2.1,0.1,0.9]})");
  EXPECT_GT(cleared["voxels_cleared"].get<int>(), 10);
  EXPECT_EQ(States({{2.01, 0.0, 0.75}, {2.01, 0.2, 0.75}, {2.5, 0.0, 0.75}}),
            (std::vector<std::string>{"free", "occupied", "unknown"}));
  const json audit = Ok("GET", "/v1/audit?map=home&action=octomap.clear")["entries"];
  ASSERT_EQ(audit.size(), 1u) << audit.dump();
  EXPECT_EQ(audit[0]["status"], 200);
  const json& before = audit[0]["before"];
  const json& after = audit[0]["after"];
  ASSERT_TRUE(before.is_object() && after.is_object()) << audit[0].dump();
  EXPECT_LT(after["occupied_leaves"].get<int>(), before["occupied_leaves"].get<int>());

  // Decay by age: nothing is a day old; everything is older than "now" with age 0.
  EXPECT_EQ(Ok("POST", "/v1/maps/home/octomap:decay", R"({"max_age_s":86400})")["voxels_forgotten"], 0);
  auto [future, error] = Send("POST", "/v1/maps/home/octomap:decay", R"({"max_age_s":0,"now":"2200-01-01T00:00:00Z"})");
  EXPECT_EQ(future, 422);
  EXPECT_EQ(error["error"]["field"], "now");
  const json decayed = Ok("POST", "/v1/maps/home/octomap:decay", R"({"max_age_s":0})");
  EXPECT_GT(decayed["voxels_forgotten"].get<int>(), 100);
  EXPECT_EQ(decayed["octomap"]["leaves"], 0);
  EXPECT_EQ(States({{2.01, 0.2, 0.75}}), (std::vector<std::string>{"unknown"}));
  EXPECT_EQ(Ok("GET", "/v1/audit?map=home&action=octomap.decay")["entries"].size(), 3u);
}

TEST_F(OctomapHttpTest, BadInputGetsAClearErrorAndChangesNothing) {
  Ok("POST", "/v1/maps", R"({"id":"home"})", "application/json", 201);
  const std::string cloud = engine::EncodeCloud(Wall(2.0f, -0.25f), engine::CloudFormat::kPcdAscii);
  Ok("POST", "/v1/maps/home/octomap/points?origin=0,0,0.75", cloud, "text/plain");
  const std::string ot = GetBytes("/v1/maps/home/octomap?format=ot");
  const std::string bt = GetBytes("/v1/maps/home/octomap?format=bt");
  const std::string points = "/v1/maps/home/octomap/points?origin=0,0,0.75";

  // Trees: wrong magic, truncated, an .ot given as .bt.
  ExpectRefused("PUT", "/v1/maps/home/octomap?format=bt", "# Octomap OcTree binary fil\nid OcTree\n", 400, "body", "application/octet-stream");
  ExpectRefused("PUT", "/v1/maps/home/octomap?format=bt", bt.substr(0, bt.size() - 40), 400, "body", "application/octet-stream");
  ExpectRefused("PUT", "/v1/maps/home/octomap?format=ot", ot.substr(0, ot.size() / 2), 400, "body", "application/octet-stream");
  ExpectRefused("PUT", "/v1/maps/home/octomap?format=bt", ot, 400, "body", "application/octet-stream");
  ExpectRefused("PUT", "/v1/maps/home/octomap", "hello", 400, "body", "application/octet-stream");
  // Absurd parameters; a resolution change of a tree that holds voxels.
  ExpectRefused("PUT", "/v1/maps/home/octomap", R"({"resolution_m":0})", 422, "resolution_m");
  ExpectRefused("PUT", "/v1/maps/home/octomap", R"({"resolution_m":1e9})", 422, "resolution_m");
  ExpectRefused("PUT", "/v1/maps/home/octomap", R"({"prob_hit":0.2})", 422, "prob_hit");
  ExpectRefused("PUT", "/v1/maps/home/octomap", R"({"resolution_m":0.1})", 409, "resolution_m");
  ExpectRefused("PUT", "/v1/maps/home/octomap", R"({"resolution":0.1})", 400, "resolution");
  // A PCD whose header lies about its points, NaN points, an origin inside the wall, no origin, a point far out.
  std::string lying = engine::EncodeCloud(Wall(2.0f, -0.25f), engine::CloudFormat::kPcdBinary);
  lying = lying.substr(0, lying.size() - 1000);
  ExpectRefused("POST", points, lying, 400, "body", "application/octet-stream");
  std::string lying_ascii = cloud;
  const std::string count = "POINTS " + std::to_string(51 * 51);
  lying_ascii.replace(lying_ascii.find(count), count.size(), "POINTS 99999999");
  ExpectRefused("POST", points, lying_ascii, 400, "body", "application/octet-stream");
  std::vector<Eigen::Vector3f> with_nan = Wall(1.0f, 0.0f);
  with_nan[5].x() = std::numeric_limits<float>::quiet_NaN();
  const std::string nan_cloud = engine::EncodeCloud(with_nan, engine::CloudFormat::kPcdBinary);
  ExpectRefused("POST", points, nan_cloud, 422, "points", "application/octet-stream");
  ExpectRefused("POST", "/v1/maps/home/octomap/points?origin=2.01,0,0.75", cloud, 422, "origin", "application/octet-stream");
  ExpectRefused("POST", "/v1/maps/home/octomap/points", cloud, 400, "origin", "application/octet-stream");
  ExpectRefused("POST", points, engine::EncodeCloud({{1e7f, 0, 0}}, engine::CloudFormat::kPcdBinary), 422, "points",
                "application/octet-stream");
  ExpectRefused("POST", points, "not a cloud", 400, "body", "application/octet-stream");
  // Queries: a non-finite point, a zero direction, an inverted box, an unknown map.
  auto [code, j] = Send("POST", "/v1/maps/home/octomap/query", R"({"points":[[0,0,"x"]]})");
  EXPECT_EQ(code, 400) << j.dump();
  ExpectRefused("POST", "/v1/maps/home/octomap/ray", R"({"origin":[0,0,0],"direction":[0,0,0]})", 422, "direction");
  ExpectRefused("POST", "/v1/maps/home/octomap:clear", R"({"min":[1,1,1],"max":[0,0,0]})", 422, "min");
  auto [unknown, e] = Send("POST", "/v1/maps/nowhere/octomap/points?origin=0,0,0", cloud, "application/octet-stream");
  EXPECT_EQ(unknown, 404);
  EXPECT_EQ(e["error"]["field"], "map");

  // The NaN cloud goes in when the client asks to skip the non-finite points.
  const json skipped = Ok("POST", points + "&skip_nonfinite=true", nan_cloud, "application/octet-stream");
  EXPECT_EQ(skipped["skipped_nonfinite"], 1);
  EXPECT_EQ(GetBytes("/v1/maps/home/octomap?format=bt").size() > 0, true);
}

TEST_F(OctomapHttpTest, BandsProjectOnTheBaseLayersGridAndExportAsMapServerMaps) {
  Ok("POST", "/v1/maps", R"({"id":"home"})", "application/json", 201);
  // An imported base layer: 80 x 60 cells at 0.05 m from (-1, -1.5), all free.
  std::string pgm = "P5\n80 60\n255\n" + std::string(80 * 60, static_cast<char>(254));
  const std::string yaml = "image: base.pgm\nresolution: 0.05\norigin: [-1.0, -1.5, 0.0]\nnegate: 0\n"
                           "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  httplib::MultipartFormDataItems parts = {{"yaml", yaml, "base.yaml", "application/yaml"},
                                           {"image", pgm, "base.pgm", "image/x-portable-graymap"}};
  httplib::Result imported = client_->Put("/v1/maps/home/layers/floor", parts);
  ASSERT_TRUE(imported && imported->status == 201) << (imported ? imported->body : "");
  // A wall at x = 2 m from z = 0.5 to 1.0 (in the "spine" band, not the "base" band), seen from (0, 0, 0.75).
  Ok("POST", "/v1/maps/home/octomap/points?origin=0,0,0.75",
     engine::EncodeCloud(Wall(2.0f, -0.25f), engine::CloudFormat::kPcdBinary), "application/octet-stream");
  const json projected = Ok("POST", "/v1/maps/home/octomap:project",
      R"({"bands":[{"layer":"base_band","min_z_m":0.0,"max_z_m":0.3},{"layer":"spine_band","min_z_m":0.5,"max_z_m":1.0}]})");
  EXPECT_EQ(projected["geometry_from"], "layer floor");
  EXPECT_EQ(projected["geometry"]["width_cells"], 80);
  EXPECT_EQ(projected["geometry"]["height_cells"], 60);
  ASSERT_EQ(projected["bands"].size(), 2u);
  EXPECT_EQ(projected["bands"][0]["cells"]["occupied"], 0);   // nothing solid below 0.3 m
  EXPECT_GT(projected["bands"][1]["cells"]["occupied"].get<int>(), 5);  // the wall
  EXPECT_GT(projected["bands"][1]["cells"]["free"].get<int>(), 20);     // the rays to it
  EXPECT_GT(projected["bands"][1]["cells"]["unknown"].get<int>(), 3000);  // everything else stays unknown
  // The exported map_server pair: the base layer's geometry, trinary values only.
  const std::string band_yaml = GetBytes("/v1/maps/home/layers/spine_band?format=yaml");
  EXPECT_NE(band_yaml.find("resolution: 0.05"), std::string::npos) << band_yaml;
  EXPECT_NE(band_yaml.find("origin: [-1"), std::string::npos) << band_yaml;
  const std::string band_pgm = GetBytes("/v1/maps/home/layers/spine_band?format=pgm");
  ASSERT_GT(band_pgm.size(), 80u * 60u);
  std::map<int, int> values;
  for (std::size_t k = band_pgm.size() - 80 * 60; k < band_pgm.size(); ++k) ++values[static_cast<std::uint8_t>(band_pgm[k])];
  EXPECT_EQ(values.size(), 3u);
  EXPECT_GT(values[0], 5);
  EXPECT_GT(values[205], 3000);
  // The wall's cell (x = 2.0 .. 2.05 m: column 60; y = 0: row 60 - 1 - 30) is black in the image.
  EXPECT_EQ(static_cast<std::uint8_t>(band_pgm[band_pgm.size() - 80 * 60 + (60 - 1 - 30) * 80 + 60]), 0);
  // Projecting again replaces the layers (next version); bad bands change nothing.
  const json again = Ok("POST", "/v1/maps/home/octomap:project", R"({"layer":"spine_band","min_z_m":0.5,"max_z_m":1.0})");
  EXPECT_EQ(again["bands"][0]["version"], 2);
  auto [code, error] = Send("POST", "/v1/maps/home/octomap:project", R"({"layer":"x","min_z_m":1.0,"max_z_m":0.5})");
  EXPECT_EQ(code, 422);
  EXPECT_EQ(error["error"]["field"], "bands");
  auto [missing, e2] = Send("POST", "/v1/maps/home/octomap:project", R"({"layer":"x","min_z_m":0,"max_z_m":1,"like":"nope"})");
  EXPECT_EQ(missing, 404);
  auto [absent, e3] = Send("GET", "/v1/maps/home/layers/x", "");
  EXPECT_EQ(absent, 404);
}

}  // namespace
}  // namespace anchordb
