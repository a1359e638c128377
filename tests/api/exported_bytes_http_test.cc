// A service's typed exported bytes become the content type and X- headers clients read (api/exported_bytes_http.h).
#include "api/exported_bytes_http.h"

#include <gtest/gtest.h>

namespace anchordb::api {
namespace exported_bytes_http_test {

using services::BytesFormat;
using services::ExportedLayer;

TEST(ExportedBytesHttp, FormatsAndDescriptionsBecomeContentTypesAndHeaders) {
  ExportedLayer raw{.format = BytesFormat::kRaw, .body = "abcd", .element = services::RawElement::kF32LogOddsCellOrder};
  raw.grid_width_cells = 40;
  raw.grid_height_cells = 30;
  raw.layer_version = 7;
  const Response r = BytesResponse(raw);
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "application/octet-stream");
  EXPECT_EQ(r.body, "abcd");
  EXPECT_EQ(r.headers.at("X-Element"), "f32-log-odds-cell-order");
  EXPECT_EQ(r.headers.at("X-Grid-Width"), "40");
  EXPECT_EQ(r.headers.at("X-Grid-Height"), "30");
  EXPECT_EQ(r.headers.at("X-Layer-Version"), "7");
  EXPECT_EQ(r.headers.count("X-Points"), 0u);

  ExportedLayer cloud{.format = BytesFormat::kPly, .body = "ply"};
  cloud.points = 12;
  cloud.frame = services::CoordinateFrame::kCamera;
  cloud.truncated = true;
  const Response c = BytesResponse(cloud);
  EXPECT_EQ(c.content_type, "application/x-ply");
  EXPECT_EQ(c.headers.at("X-Points"), "12");
  EXPECT_EQ(c.headers.at("X-Frame"), "camera");
  EXPECT_EQ(c.headers.at("X-Truncated"), "true");
  EXPECT_EQ(c.headers.count("X-Element"), 0u);

  ExportedLayer tree{.format = BytesFormat::kOctomapBinary, .body = "bt"};
  tree.octomap_version = 3;
  tree.file_name = "home.bt";
  const Response t = BytesResponse(tree);
  EXPECT_EQ(t.headers.at("X-Octomap-Version"), "3");
  EXPECT_EQ(t.headers.at("Content-Disposition"), "attachment; filename=\"home.bt\"");

  EXPECT_STREQ(ContentTypeOf(BytesFormat::kPng), "image/png");
  EXPECT_STREQ(ContentTypeOf(BytesFormat::kPgm), "image/x-portable-graymap");
  EXPECT_STREQ(ContentTypeOf(BytesFormat::kMapServerYaml), "application/yaml");
  EXPECT_STREQ(ContentTypeOf(BytesFormat::kPcd), "application/x-pcd");
}

}  // namespace
}  // namespace anchordb::api
